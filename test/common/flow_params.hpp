#pragma once
// Test flow-model parameters shared by the chamber tests: a grid of bands x sectors, no choke feed, prefill as asked.
#include "chamber/flow_model.hpp"

namespace test_liners {

inline chamber::FlowParams flow_params(int bands, int sectors, bool prefill = false) {
  chamber::FlowParams p;
  p.bands = bands;
  p.sectors = sectors;
  p.prefill = prefill;
  p.choke_feed = false;
  return p;
}

}  // namespace test_liners
