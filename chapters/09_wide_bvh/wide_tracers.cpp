// Chapter 09: the chapter's trees as tracers. See wide_tracers.h.
#include "wide_tracers.h"

#include <memory>
#include <optional>

#include "bvh_build.h"
#include "memory_tracers.h"
#include "model_render.h"
#include "rt/error.h"
#include "wide_trace.h"

namespace rt::ch09 {
namespace {

using ch07::Tracer;
using ch07::TracerScene;

struct TracerInfo {
  ChapterTracer tracer;
  const char* name;
  const char* option;
};

constexpr TracerInfo k_info[] = {
    {ChapterTracer::binary, "binary (ch07)", "binary"},
    {ChapterTracer::wide4, "wide4", "wide4"},
    {ChapterTracer::wide8, "wide8", "wide8"},
    {ChapterTracer::cwbvh8, "cwbvh8", "cwbvh8"},
    {ChapterTracer::cwbvh8_greedy, "cwbvh8 greedy", "cwbvh8_greedy"},
};

const TracerInfo& info(ChapterTracer tracer) {
  for (const TracerInfo& i : k_info)
    if (i.tracer == tracer) return i;
  throw Error("unknown chapter tracer");
}

// A stored wide tree as a tracer: shared by its functions, on the GPU uploaded once.
template <class Node>
Tracer wide_tracer(ChapterTracer which, WideTree<Node> built, const TracerScene& scene) {
  const auto tree = std::make_shared<const WideTree<Node>>(std::move(built));
  Tracer tracer;
  tracer.name = to_string(which);
  tracer.rule = ch07::HitRule::ties_allowed;
  tracer.bytes_per_triangle = tree->stats.bytes_per_triangle;
  tracer.trace_cpu = [tree](Query query, std::span<const RayF> rays, std::span<MeshHit> hits) {
    trace_wide_cpu(query, tree->view(), rays, hits);
  };
  tracer.work = [tree](Query query, std::span<const RayF> rays) {
    return measure_wide_work(query, tree->view(), rays);
  };
  if (scene.backend == Backend::gpu) {
    ch05::check_device_memory(tree->nodes.size() * sizeof(Node) +
                                  tree->triangles.size() * sizeof(float4),
                              scene.name);
    const auto d_tree = std::make_shared<const DeviceWideTree<Node>>(*tree);
    tracer.trace_gpu = [d_tree](Query query, const RayF* d_rays, int count, MeshHit* d_hits) {
      trace_wide_gpu(query, d_tree->view(), d_rays, count, d_hits);
    };
    tracer.registers = [](Query query) { return wide_kernel_registers<Node>(query); };
  }
  return tracer;
}

// One scene's binary trees, each built once, whichever tracers ask.
class BinaryTrees {
public:
  explicit BinaryTrees(const TracerScene& scene) : scene_(scene) {}
  const ch07::Bvh& for_collapse(Collapse collapse) {
    std::optional<ch07::Bvh>& tree = collapse == Collapse::sah ? sah_ : greedy_;
    if (!tree)
      tree = ch07::build_bvh(scene_.mesh, binary_options(collapse, scene_.bvh.options));
    return *tree;
  }

private:
  const TracerScene& scene_;
  std::optional<ch07::Bvh> sah_, greedy_;
};

Tracer make_wide(ChapterTracer which, BinaryTrees& binary, const TracerScene& scene,
                 const BuildSink& on_build) {
  const Collapse collapse =
      which == ChapterTracer::cwbvh8_greedy ? Collapse::greedy : Collapse::sah;
  const int width = which == ChapterTracer::wide4 ? 4 : 8;
  const ch07::Bvh& tree = binary.for_collapse(collapse);
  WideLayout layout = ch09::collapse(tree, width, collapse);
  layout.stats.build_ms += tree.stats.build_ms;
  const auto report = [&](const WideStats& stats) {
    if (on_build) on_build(scene.name, to_string(which), stats);
  };
  if (which == ChapterTracer::wide4) {
    Wide4Bvh stored = pack_wide<4>(layout);
    report(stored.stats);
    return wide_tracer(which, std::move(stored), scene);
  }
  if (which == ChapterTracer::wide8) {
    Wide8Bvh stored = pack_wide<8>(layout);
    report(stored.stats);
    return wide_tracer(which, std::move(stored), scene);
  }
  CompressedBvh stored = compress(layout);
  report(stored.stats);
  return wide_tracer(which, std::move(stored), scene);
}

} // namespace

const char* to_string(ChapterTracer tracer) { return info(tracer).name; }
const char* option_name(ChapterTracer tracer) { return info(tracer).option; }

ChapterTracer parse_tracer(std::string_view name) {
  std::string names;
  for (const TracerInfo& i : k_info) {
    if (name == i.option) return i.tracer;
    names += std::string(names.empty() ? "" : ", ") + i.option;
  }
  throw UsageError("--tracer " + std::string(name) + ": the tracers are " + names);
}

ch07::TracerMaker chapter_tracers(std::vector<ChapterTracer> tracers, BuildSink on_build) {
  return [tracers, on_build](const TracerScene& scene) {
    std::vector<Tracer> out;
    BinaryTrees binary(scene);
    for (const ChapterTracer which : tracers) {
      if (which != ChapterTracer::binary) {
        out.push_back(make_wide(which, binary, scene, on_build));
        continue;
      }
      for (Tracer& kept :
           ch08::kept_tracer()(scene)) { // the binary tree, as chapter 08 keeps it
        kept.name = to_string(ChapterTracer::binary);
        out.push_back(std::move(kept));
      }
    }
    return out;
  };
}

} // namespace rt::ch09
