#include "nodes/dem_node_cloud.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

namespace nodes {

sensor_msgs::PointCloud2 particle_cloud(const ros::Time& stamp, const dem::Particles& p,
                                        const std::vector<int>& fragment) {
  if (fragment.size() != p.size())
    throw std::invalid_argument("particle_cloud: " + std::to_string(fragment.size()) + " fragment labels for " +
                                std::to_string(p.size()) + " particles");
  static const char* names[] = {"x", "y", "z", "radius", "fragment", "vx", "vy", "vz", "fx", "fy", "fz"};
  constexpr int kFields = 11, kFragment = 4;
  sensor_msgs::PointCloud2 c;
  c.header.stamp = stamp;
  c.header.frame_id = "world";
  for (int k = 0; k < kFields; ++k) {
    sensor_msgs::PointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = k == kFragment ? sensor_msgs::PointField::INT32 : sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  c.height = 1;
  c.width = static_cast<uint32_t>(p.size());
  c.is_bigendian = false;  // memcpy below: this host's order, little endian on every machine we build for
  c.point_step = 4 * kFields;
  c.row_step = c.point_step * c.width;
  c.is_dense = true;
  c.data.resize(static_cast<std::size_t>(c.row_step));
  uint8_t* d = c.data.data();
  for (std::size_t i = 0; i < p.size(); ++i, d += c.point_step) {
    const float v[kFields] = {float(p.x[i]),  float(p.y[i]),  float(p.z[i]),  float(p.r[i]),
                              0.0f,           float(p.vx[i]), float(p.vy[i]), float(p.vz[i]),
                              float(p.fx[i]), float(p.fy[i]), float(p.fz[i])};
    std::memcpy(d, v, sizeof v);
    const int32_t frag = fragment[i];
    std::memcpy(d + 4 * kFragment, &frag, 4);
  }
  return c;
}

}  // namespace nodes
