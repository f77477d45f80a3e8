#pragma once
// Test flow-model parameters shared by the chamber tests: a grid of bands x sectors, no choke feed, prefill as asked.
#include <memory>
#include <sstream>

#include "chamber/flow_model.hpp"
#include "core/binary_io.hpp"

namespace test_liners {

inline chamber::FlowParams flow_params(int bands, int sectors, bool prefill = false) {
  chamber::FlowParams p;
  p.bands = bands;
  p.sectors = sectors;
  p.prefill = prefill;
  p.choke_feed = false;
  return p;
}

// A model of p on the given liners that continues from m's state, through a checkpoint stream.
inline std::unique_ptr<chamber::FlowModel> resumed(const chamber::FlowModel& m, const chamber::FlowParams& p,
                                                   const core::Profile& mantle, const core::Profile& concave) {
  std::stringstream file;
  core::BinaryWriter w(file);
  m.save_state(w);
  auto copy = std::make_unique<chamber::FlowModel>(p, mantle, concave);
  core::BinaryReader r(file, "flow test checkpoint");
  copy->load_state(r);
  return copy;
}

}  // namespace test_liners
