// Chapter 07, optional: our CPU traversal of the chapter's SAH tree measured against Embree 3
// on the same cores and the very same rays, with the hits of the two compared ray by ray
// (embree_comparison.h). Built only where Embree is installed.
//
//   ch07_embree_compare [--width W --height H] [--threads N] [--runs N] [--json FILE]
//                       [--robust] [--backend cpu] SCENE...
#include <string>

#include "embree_comparison.h"
#include "rt/report.h"

namespace {

// The build's own thread count (bvh_build.h): the CPU backend's, as Embree's build gets.
std::string build_label(int threads) {
  return "binned SAH, " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
}

} // namespace

int main(int argc, char** argv) {
  using namespace rt::ch07;
  const EmbreeCompareProgram program{
      .name = "ch07_embree_compare",
      .title = "Chapter 07: our CPU traversal against Embree's, same rays, same cores",
      .report_title = "Chapter 07: our CPU traversal against Embree",
      .tracers = {"sah"},
      // The comparison's own tree, chapter 07's SAH build, read by trace_bvh.
      .make_ours =
          [](const std::string&, const TracerScene& scene) {
            return OursOnScene{.tracer = chapter07_tracers(scene).at(0),
                               .build_ms = scene.bvh.stats.build_ms,
                               .build = build_label(scene.bvh.stats.threads),
                               .cost =
                                   "SAH cost " + rt::format_fixed(scene.bvh.stats.sah_cost, 1)};
          },
  };
  return run_embree_compare(argc, argv, program);
}
