// Chapter 10: the builders as tracers. See builders.h.
#include "builders.h"

#include <algorithm>
#include <vector>

#include <sstream>

#include "bvh_build.h"
#include "collapse.h"
#include "gpu_build.h"
#include "rt/error.h"
#include "wide_collapse.h"
#include "wide_tracers.h"

namespace rt::ch10 {
namespace {

struct BuilderInfo {
  Builder builder;
  const char* name;
  const char* option;
};

constexpr BuilderInfo k_info[] = {
    {Builder::cpu_sah, "CPU SAH (ch07)", "cpu_sah"},
    {Builder::lbvh, "LBVH", "lbvh"},
    {Builder::lbvh63, "LBVH 63-bit", "lbvh63"},
    {Builder::ploc, "PLOC", "ploc"},
    {Builder::hploc, "H-PLOC", "hploc"},
    {Builder::hploc_treelets, "H-PLOC + treelets", "hploc_treelets"},
};

const BuilderInfo& info(Builder builder) {
  for (const BuilderInfo& i : k_info)
    if (i.builder == builder) return i;
  throw Error("unknown builder");
}

} // namespace

const char* to_string(Builder builder) { return info(builder).name; }

Builder parse_builder(std::string_view name) {
  std::string names;
  for (const BuilderInfo& i : k_info) {
    if (name == i.option) return i.builder;
    names += std::string(names.empty() ? "" : ", ") + i.option;
  }
  throw UsageError("--builder " + std::string(name) + ": the builders are " + names);
}

namespace {

// [listing:timed_builds]
// A GPU build timed once says as much about the driver as about the build: the first launch
// of each kernel also loads its code (CUDA loads modules lazily), and the clock runs on a GPU
// that may still be waking up. So on the GPU `build` (which makes a tree into a variable of
// the caller and returns its time) runs k_timed_builds + 1 times, the first untimed, and the
// median time is kept (the benchmark protocol's rule for kernels); the tree is the same every
// time. On the CPU it runs once.
constexpr int k_timed_builds = 5;
template <class Build> double median_build_ms(Backend backend, Build&& build) {
  const double once = build();
  if (backend != Backend::gpu) return once;
  std::vector<double> ms;
  for (int run = 0; run < k_timed_builds; ++run) ms.push_back(build());
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}
template <class Make> GpuBuild timed_build(Backend backend, Make&& make) {
  GpuBuild built;
  const double ms = median_build_ms(backend, [&] {
    built = make();
    return built.build_ms;
  });
  built.build_ms = built.bvh.stats.build_ms = ms;
  return built;
}
// [/listing:timed_builds]

} // namespace

BuiltTree build_tree(Builder builder, Backend backend, const ch04::Mesh& mesh) {
  switch (builder) {
  case Builder::cpu_sah: {
    ch07::BuildOptions options;
    options.max_leaf_size = 1; // as the others, and as chapter 09's SAH collapse wants it
    return {ch07::build_bvh(mesh, options), Backend::cpu, ""};
  }
  case Builder::lbvh:
  case Builder::lbvh63: {
    GpuBuild build = timed_build(backend, [&] {
      return build_lbvh(backend, mesh,
                        builder == Builder::lbvh ? CodeWidth::bits30 : CodeWidth::bits63);
    });
    return {std::move(build.bvh), backend, std::move(build.note)};
  }
  case Builder::ploc: {
    GpuBuild build = timed_build(backend, [&] { return build_ploc(backend, mesh); });
    return {std::move(build.bvh), backend, std::move(build.note)};
  }
  case Builder::hploc:
  case Builder::hploc_treelets: {
    const int rounds = builder == Builder::hploc ? 0 : k_treelet_rounds;
    GpuBuild build = timed_build(backend, [&] {
      return build_hploc(backend, mesh, k_ploc_radius, k_hploc_threshold, rounds);
    });
    return {std::move(build.bvh), backend, std::move(build.note)};
  }
  }
  throw Error("unknown builder");
}

ReportRow build_row(const std::string& scene, Builder builder, const BuiltTree& tree) {
  const ch07::BuildStats& s = tree.bvh.stats;
  const double triangles = double(tree.bvh.triangles.size());
  return {scene + ", build " + to_string(builder),
          to_string(tree.backend),
          s.build_ms,
          s.build_ms > 0 ? triangles / (s.build_ms * 1e3) : 0.0,
          group_digits(s.nodes) + " nodes, depth " + std::to_string(s.depth) + ", SAH cost " +
              format_fixed(s.sah_cost, 1) + "; collapse to 4-wide " +
              format_fixed(tree.collapse_ms, 2) + " ms (depth rule " +
              format_fixed(tree.collapse_depth_ms, 2) + " ms) (Mtriangles/s)" +
              (tree.note.empty() ? "" : "; " + tree.note),
          {{"triangles", triangles},
           {"nodes", double(s.nodes)},
           {"depth", double(s.depth)},
           {"sah_cost", s.sah_cost},
           {"collapse_ms", tree.collapse_ms},
           {"collapse_depth_ms", tree.collapse_depth_ms}}};
}

ch07::TracerMaker builder_tracers(std::vector<Builder> builders, BuildSink on_build,
                                  CollapseRule rule) {
  return [builders, on_build, rule](const ch07::TracerScene& scene) {
    std::vector<ch07::Tracer> out;
    for (const Builder builder : builders) {
      BuiltTree tree = build_tree(builder, scene.backend, scene.mesh);
      // Both collapses timed as the builds are; `rule`'s tree kept.
      ch09::Wide4PackedBvh parallel;
      const auto timed_collapse = [&](CollapseRule timed) {
        return median_build_ms(scene.backend, [&] {
          ch09::Wide4PackedBvh wide = collapse_to_wide4(scene.backend, tree.bvh, timed);
          const double ms = wide.stats.build_ms;
          if (timed == rule) parallel = std::move(wide);
          return ms;
        });
      };
      tree.collapse_ms = timed_collapse(CollapseRule::sah);
      tree.collapse_depth_ms = timed_collapse(CollapseRule::depth);
      parallel.stats.build_ms =
          rule == CollapseRule::sah ? tree.collapse_ms : tree.collapse_depth_ms;
      parallel.stats.build_ms += tree.bvh.stats.build_ms;
      if (on_build) on_build(scene.name, builder, tree);
      const ch09::WideLayout layout = ch09::collapse(tree.bvh, 4, ch09::Collapse::sah);
      ch07::Tracer binary = ch07::bvh_tracer(to_string(builder), std::move(tree.bvh), scene);
      binary.rule = ch07::HitRule::ties_allowed; // another tree: exact ties may go either way
      out.push_back(std::move(binary));
      out.push_back(ch09::wide4_tracer(std::string(to_string(builder)) + " 4-wide",
                                       ch09::pack_wide<4, ch09::PackedTriangles>(layout),
                                       scene));
      out.push_back(ch09::wide4_tracer(std::string(to_string(builder)) +
                                           " 4-wide (parallel collapse" +
                                           (rule == CollapseRule::sah ? ")" : ", depth rule)"),
                                       std::move(parallel), scene));
    }
    return out;
  };
}

std::string build_table(const std::vector<std::pair<Builder, BuiltTree>>& builds) {
  std::ostringstream out;
  out << "\n| builder | built on | build ms | + 4-wide collapse ms: sah / depth rule | SAH "
         "cost "
         "| depth | nodes |\n"
      << "|---|---|---:|---:|---:|---:|---:|\n";
  for (const auto& [builder, tree] : builds) {
    const ch07::BuildStats& s = tree.bvh.stats;
    out << "| " << to_string(builder) << " | " << to_string(tree.backend) << " | "
        << format_fixed(s.build_ms, 2) << " | " << format_fixed(tree.collapse_ms, 2) << " / "
        << format_fixed(tree.collapse_depth_ms, 2) << " | " << format_fixed(s.sah_cost, 1)
        << " | " << s.depth << " | " << group_digits(s.nodes) << " |\n";
  }
  return out.str();
}

} // namespace rt::ch10
