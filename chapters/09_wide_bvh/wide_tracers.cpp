// Chapter 09: the chapter's trees as tracers. See wide_tracers.h.
#include "wide_tracers.h"

#include <memory>
#include <optional>
#include <sstream>

#include "bvh_build.h"
#include "memory_tracers.h"
#include "model_render.h"
#include "rt/device_buffer.h"
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
    {ChapterTracer::wide4_packed, "wide4 packed", "wide4_packed"},
};

const TracerInfo& info(ChapterTracer tracer) {
  for (const TracerInfo& i : k_info)
    if (i.tracer == tracer) return i;
  throw Error("unknown chapter tracer");
}

// A stored wide tree as a tracer: shared by its functions, on the GPU uploaded once.
template <class Node, class Triangles>
Tracer wide_tracer(std::string name, WideTree<Node, Triangles> built,
                   const TracerScene& scene) {
  using Tree = WideTree<Node, Triangles>;
  const auto tree = std::make_shared<const Tree>(std::move(built));
  Tracer tracer;
  tracer.name = std::move(name);
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
                                  tree->triangles.size() * sizeof(tree->triangles[0]),
                              scene.name);
    const auto d_tree = std::make_shared<const DeviceWideTree<Node, Triangles>>(*tree);
    tracer.trace_gpu = [d_tree](Query query, const RayF* d_rays, int count, MeshHit* d_hits) {
      trace_wide_gpu(query, d_tree->view(), d_rays, count, d_hits);
    };
    tracer.registers = [](Query query) {
      return wide_kernel_registers<typename Tree::View>(query);
    };
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
  const int width =
      which == ChapterTracer::wide4 || which == ChapterTracer::wide4_packed ? 4 : 8;
  const ch07::Bvh& tree = binary.for_collapse(collapse);
  WideLayout layout = ch09::collapse(tree, width, collapse);
  layout.stats.build_ms += tree.stats.build_ms;
  const auto report = [&](const WideStats& stats) {
    if (on_build) on_build(scene.name, to_string(which), stats);
  };
  if (which == ChapterTracer::wide4) {
    Wide4Bvh stored = pack_wide<4>(layout);
    report(stored.stats);
    return wide_tracer(to_string(which), std::move(stored), scene);
  }
  if (which == ChapterTracer::wide4_packed) {
    Wide4PackedBvh stored = pack_wide<4, PackedTriangles>(layout);
    report(stored.stats);
    return wide_tracer(to_string(which), std::move(stored), scene);
  }
  if (which == ChapterTracer::wide8) {
    Wide8Bvh stored = pack_wide<8>(layout);
    report(stored.stats);
    return wide_tracer(to_string(which), std::move(stored), scene);
  }
  CompressedBvh stored = compress(layout);
  report(stored.stats);
  return wide_tracer(to_string(which), std::move(stored), scene);
}

} // namespace

const char* to_string(ChapterTracer tracer) { return info(tracer).name; }

Tracer wide4_tracer(std::string name, Wide4PackedBvh tree, const TracerScene& scene) {
  return wide_tracer(std::move(name), std::move(tree), scene);
}

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
      // The binary tree, as chapter 08 keeps it; its work counted by chapter 07's counters.
      const auto bvh = std::make_shared<const ch07::Bvh>(scene.bvh);
      for (Tracer& kept : ch08::kept_tracer()(scene)) {
        kept.name = to_string(ChapterTracer::binary);
        kept.work = [bvh](Query query, std::span<const RayF> rays) {
          return ch07::measure_work(query, ch04::TriangleVariant::watertight, bvh->view(),
                                    rays);
        };
        out.push_back(std::move(kept));
      }
    }
    return out;
  };
}

ReportRow build_row(const std::string& scene, const std::string& tracer, const WideStats& s) {
  return {scene + ", build " + tracer + " (CPU)",
          "cpu",
          s.build_ms,
          0.0,
          group_digits(s.nodes) + " nodes, depth " + std::to_string(s.depth) + ", " +
              format_fixed(s.children_per_node, 1) + " children per node, " +
              format_fixed(s.triangles_per_leaf, 2) + " triangles per leaf, SAH cost " +
              format_fixed(s.sah_cost, 1) + ", " + format_fixed(s.bytes_per_triangle, 1) +
              " B/triangle",
          {{"nodes", double(s.nodes)},
           {"depth", double(s.depth)},
           {"children_per_node", s.children_per_node},
           {"triangles_per_leaf", s.triangles_per_leaf},
           {"sah_cost", s.sah_cost},
           {"bytes_per_triangle", s.bytes_per_triangle}}};
}

std::string memory_table(const std::vector<ch07::SceneResult>& results) {
  std::ostringstream out;
  out << "\nbytes per triangle (nodes and triangle records; in brackets: against "
      << to_string(ChapterTracer::binary) << ")\n\n| scene |";
  for (const ChapterTracer t : k_all_tracers) out << " " << to_string(t) << " |";
  out << "\n|---|";
  for (std::size_t k = 0; k < std::size(k_all_tracers); ++k) out << "---|";
  out << "\n";
  for (const ch07::SceneResult& r : results) {
    const ch07::TracerFigure* binary =
        r.find(to_string(ChapterTracer::binary), ch07::RayType::primary);
    out << "| " << r.scene << " |";
    for (const ChapterTracer t : k_all_tracers) {
      const ch07::TracerFigure* f = r.find(to_string(t), ch07::RayType::primary);
      if (f == nullptr) {
        out << " - |";
        continue;
      }
      out << " " << format_fixed(f->bytes_per_triangle, 1);
      if (binary != nullptr && binary->bytes_per_triangle > 0)
        out << " (" << format_fixed(f->bytes_per_triangle / binary->bytes_per_triangle, 2)
            << "x)";
      out << " |";
    }
    out << "\n";
  }
  return out.str();
}

} // namespace rt::ch09
