#pragma once
// radar_ndt_bench's three benchmarks (docs/apps.md): the matchers on synthetic radar-like scan pairs
// with known transforms (ndt_bench_synthetic.cpp), the registered matchers on real nuScenes submap
// pairs and the scanning front-end's two paths on an Oxford-layout sequence (ndt_bench_real.cpp).
// Each prints a table, or with `json` one JSON object.

#include <cstdint>
#include <string>
#include <vector>

namespace radar_ndt {
namespace apps {

/// Real submap pairs: N = 3 probabilistic submaps of consecutive cycles of every scene under
/// `dataroot` (every `stride`-th cycle), each registered matcher that needs no Doppler weights
/// started from the Doppler integral; errors against the ground-truth motion.
int benchNuScenes(const std::string& dataroot, std::size_t stride, bool json);

/// The scanning front-end's two paths on the consecutive scan pairs of an Oxford-layout sequence.
int benchScanningFrontEnds(const std::string& dir, bool json);

/// The synthetic benchmark's settings (the command line's).
struct SyntheticBench {
  std::size_t pairs = 24, repeats = 1;
  std::string sizes_text = "5000,10000,20000";
  std::vector<std::size_t> sizes;
  std::uint32_t seed = 1;
  double grid = 3.0, shift = 0.3, noise = 0.05, clutter = 0.15, max_t = 2.0, max_r = 3.0, icp_dist = 5.0;
  bool with_icp = true, with_ndt2d = true, variants = false, json = false;
};

/// Every method aligns the same synthetic pairs from the identity: time, errors, convergence.
int benchSynthetic(const SyntheticBench& bench);

}  // namespace apps
}  // namespace radar_ndt
