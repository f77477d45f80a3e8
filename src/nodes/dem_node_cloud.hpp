#pragma once
// /crusher/particle_state: one PointCloud2 point per DEM particle, for export and analysis (the markers on
// /crusher/particles carry neither fragment, velocity nor force).
// Fields, little endian, 44 bytes a point: x y z (m), radius (m), fragment (int32: connected component over
// intact bonds), vx vy vz (m/s), fx fy fz (N: total force of the last DEM step, gravity included); float32 but
// fragment. Frame `world`.
#include <ros/time.h>
#include <sensor_msgs/PointCloud2.h>

#include <vector>

#include "dem/particles.hpp"

namespace nodes {

// fragment[i]: the fragment label of particle i (coupling::ChamberDem::fragment_labels), one per particle.
sensor_msgs::PointCloud2 particle_cloud(const ros::Time& stamp, const dem::Particles& p,
                                        const std::vector<int>& fragment);

}  // namespace nodes
