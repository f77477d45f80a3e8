#pragma once
// Worn liners (flow.effects.worn_liners): the concave worn over the lower chamber, the wear growing toward the
// discharge, as liners wear where the crushing force is largest (paper section 4.2.3: the force grows toward the
// bottom rings). The whole wear is put on the concave (what the flow model's gap sees is the sum of both liners').
#include "chamber/flow_model.hpp"
#include "core/chamber_geometry.hpp"

namespace chamber {

// Normal wear depth (m) at height z of a chamber spanning [z_lo, z_hi]: the full setting_increase at z_lo (the
// discharge), falling linearly to 0 at z_lo + worn_height_fraction (z_hi - z_lo), 0 above.
double wear_depth(const WornLiners& w, double z_lo, double z_hi, double z);

// The concave with its surface moved outward (into the liner) by wear_depth along its normal: each point's radius
// grows by depth / |t_z| (t: the profile's unit tangent), so the distance to the unworn surface is the depth on every
// straight segment. Vertices are added where the wear starts and at z_lo; z stays as it was (monotonic).
core::Profile worn_concave(const core::Profile& concave, double z_lo, double z_hi, const WornLiners& w);

}  // namespace chamber
