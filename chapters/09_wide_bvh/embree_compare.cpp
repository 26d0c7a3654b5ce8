// Chapter 09, optional: a wide tree of the chapter (by default the CPU's own, cpu8) traced on
// the CPU against Embree 3 on the same cores and the very same rays, hits compared ray by ray,
// through chapter 07's comparison (embree_comparison.h). Built only where Embree is installed.
//
//   ch09_embree_compare [--tracer NAME] [--split sah|sbvh [--split-budget B]]
//                       [--width W --height H] [--threads N] [--runs N]
//                       [--json FILE] [--robust] [--backend cpu] SCENE...
#include "embree_comparison.h"
#include "rt/backend.h"
#include "rt/report.h"
#include "wide_tracers.h"

int main(int argc, char** argv) {
  using namespace rt::ch09;
  const rt::ch07::EmbreeCompareProgram program{
      .name = "ch09_embree_compare",
      .title =
          "Chapter 09: a wide tree's CPU traversal against Embree's, same rays, same cores",
      .report_title = "Chapter 09: a wide tree on the CPU against Embree",
      // The chapter's tracers with a CPU path of their own: the shared-stack and persistent
      // variants run wide4 packed's plain traversal on the CPU (wide_tracers.cpp).
      .tracers = {"cpu8", "wide8", "wide4", "cwbvh8", "cwbvh8_greedy", "wide4_packed",
                  "wide4_packed_sorted", "binary"},
      .make_ours =
          [](const std::string& name, const rt::ch07::TracerScene& scene) {
            const ChapterTracer which = parse_tracer(name);
            // The binary tree reads chapter 07's; a wide tree is built, and timed, from the
            // mesh on (binary build, collapse, stored layout).
            WideStats wide;
            const BuildSink keep_stats = [&](const std::string&, const std::string&,
                                             const WideStats& stats) { wide = stats; };
            // The binary build's threads (one for spatial splits); the collapse and the
            // stored layout run on the build options' threads (0: the CPU backend's).
            const auto on = [](int threads) {
              return std::to_string(threads) + (threads == 1 ? " thread" : " threads");
            };
            const std::string on_threads = on(scene.bvh.stats.threads);
            const int asked = scene.bvh.options.threads;
            rt::ch07::OursOnScene ours{
                .tracer = chapter_tracers({which}, keep_stats)(scene).at(0),
                .build_ms = scene.bvh.stats.build_ms,
                .build = "binned SAH, " + on_threads,
                .cost = "SAH cost " + rt::format_fixed(scene.bvh.stats.sah_cost, 1)};
            if (which == ChapterTracer::binary) return ours;
            ours.build_ms = wide.build_ms;
            const bool spatial = scene.bvh.options.method == rt::ch07::SplitMethod::sbvh;
            ours.build =
                std::string(spatial ? "binned SAH with spatial splits" : "binned SAH") +
                " on " + on_threads + ", then " +
                (which == ChapterTracer::cwbvh8_greedy ? "greedy" : "SAH") + " collapse on " +
                on(asked > 0 ? asked : rt::cpu_thread_count());
            ours.cost =
                "SAH cost " + rt::format_fixed(wide.sah_cost, 1) + " by the collapse's model";
            return ours;
          },
  };
  return rt::ch07::run_embree_compare(argc, argv, program);
}
