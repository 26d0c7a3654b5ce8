// Chapter 09: the chapter's trees as tracers. See wide_tracers.h.
#include "wide_tracers.h"

#include <memory>
#include <optional>
#include <sstream>

#include "bvh_build.h"
#include "cpu_tree.h"
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
    {ChapterTracer::wide4_packed_shared_stack, "wide4 packed, shared stack",
     "wide4_packed_shared_stack"},
    {ChapterTracer::wide4_packed_persistent, "wide4 packed, persistent",
     "wide4_packed_persistent"},
    {ChapterTracer::wide4_packed_sorted, "wide4 packed, sorted rays", "wide4_packed_sorted"},
    {ChapterTracer::wide4_packed_tiles, "wide4 packed, tiles", "wide4_packed_tiles"},
    {ChapterTracer::wide4_packed_persistent_tiles, "wide4 packed, persistent, tiles",
     "wide4_packed_persistent_tiles"},
    {ChapterTracer::cpu8, "cpu8", "cpu8"},
};

const TracerInfo& info(ChapterTracer tracer) {
  for (const TracerInfo& i : k_info)
    if (i.tracer == tracer) return i;
  throw Error("unknown chapter tracer");
}

// A stored wide tree, shared by the tracers that read it; on the GPU uploaded once.
template <class Node, class Triangles> struct SharedTree {
  std::shared_ptr<const WideTree<Node, Triangles>> host;
  std::shared_ptr<const DeviceWideTree<Node, Triangles>> device; // null on the CPU backend
};

template <class Node, class Triangles>
SharedTree<Node, Triangles> share(WideTree<Node, Triangles> built, const TracerScene& scene) {
  SharedTree<Node, Triangles> tree;
  tree.host = std::make_shared<const WideTree<Node, Triangles>>(std::move(built));
  if (scene.backend == Backend::gpu) {
    ch05::check_device_memory(tree.host->nodes.size() * sizeof(Node) +
                                  tree.host->triangles.size() * sizeof(tree.host->triangles[0]),
                              scene.name);
    tree.device = std::make_shared<const DeviceWideTree<Node, Triangles>>(*tree.host);
  }
  return tree;
}

// A stored wide tree as a tracer, through trace_wide_cpu and trace_wide_gpu.
template <class Node, class Triangles>
Tracer wide_tracer(std::string name, const SharedTree<Node, Triangles>& tree) {
  using View = typename WideTree<Node, Triangles>::View;
  Tracer tracer;
  tracer.name = std::move(name);
  tracer.rule = ch07::HitRule::ties_allowed;
  tracer.bytes_per_triangle = tree.host->stats.bytes_per_triangle;
  tracer.trace_cpu = [host = tree.host](Query query, std::span<const RayF> rays,
                                        std::span<MeshHit> hits) {
    trace_wide_cpu(query, host->view(), rays, hits);
  };
  tracer.work = [host = tree.host](Query query, std::span<const RayF> rays) {
    return measure_wide_work(query, host->view(), rays);
  };
  if (tree.device) {
    tracer.trace_gpu = [device = tree.device](Query query, const RayF* d_rays, int count,
                                              MeshHit* d_hits) {
      trace_wide_gpu(query, device->view(), d_rays, count, d_hits);
    };
    tracer.registers = [](Query query) { return wide_kernel_registers<View>(query); };
  }
  return tracer;
}

using PackedTree = SharedTree<WideNode<4>, PackedTriangles>;
using PackedView = Wide4PackedBvh::View;

// wide4 packed's tree traversed another way: the same tree and, ray by ray, the same
// traversal, so the same hits bit for bit. Its name, rule, memory and work are wide4 packed's
// tracer's; only the paths that trace differ.
Tracer variant_tracer(ChapterTracer which, const PackedTree& tree, const TracerScene& scene) {
  Tracer tracer = wide_tracer(to_string(which), tree);
  if (which == ChapterTracer::wide4_packed_sorted) {
    ch07::Aabb bounds;
    for (const Vec3f& v : scene.mesh.vertices) bounds.grow(v);
    const RaySortFrame frame = make_ray_sort_frame(bounds);
    tracer.trace_cpu = [host = tree.host, frame](Query query, std::span<const RayF> rays,
                                                 std::span<MeshHit> hits) {
      trace_wide_sorted_cpu(query, host->view(), frame, rays, hits);
    };
    if (!tree.device) return tracer;
    const auto sorted = std::make_shared<SortedWideTracer<PackedView>>(frame);
    tracer.trace_gpu = [device = tree.device, sorted](Query query, const RayF* d_rays,
                                                      int count, MeshHit* d_hits) {
      sorted->trace(query, device->view(), d_rays, count, d_hits);
    };
    tracer.registers = SortedWideTracer<PackedView>::registers;
    return tracer;
  }
  // A shared stack, persistent threads and tiles are GPU matters: on the CPU these tracers run
  // the plain traversal (a CPU thread's stack is in its cache anyway, for_each_ray_cpu's
  // threads already take their rays in chunks from a counter, and a thread has no warp).
  if (!tree.device) return tracer;
  // The tiles are the camera's image's: a batch of exactly its pixel count is taken in tiles.
  const int width = scene.camera.width, height = scene.camera.height;
  if (which == ChapterTracer::wide4_packed_tiles) {
    tracer.trace_gpu = [device = tree.device, width, height](Query query, const RayF* d_rays,
                                                             int count, MeshHit* d_hits) {
      trace_wide_gpu(query, device->view(), d_rays, count, d_hits,
                     RayOrder::for_image(count, width, height));
    };
    return tracer;
  }
  if (which == ChapterTracer::wide4_packed_shared_stack) {
    tracer.trace_gpu = [device = tree.device](Query query, const RayF* d_rays, int count,
                                              MeshHit* d_hits) {
      trace_wide_gpu_shared_stack(query, device->view(), d_rays, count, d_hits);
    };
    tracer.registers = shared_stack_kernel_registers<PackedView>;
    return tracer;
  }
  const auto persistent = std::make_shared<PersistentWideTracer<PackedView>>();
  const bool tiles = which == ChapterTracer::wide4_packed_persistent_tiles;
  tracer.trace_gpu = [device = tree.device, persistent, tiles, width,
                      height](Query query, const RayF* d_rays, int count, MeshHit* d_hits) {
    persistent->trace(query, device->view(), d_rays, count, d_hits,
                      tiles ? RayOrder::for_image(count, width, height) : RayOrder{});
  };
  tracer.registers = PersistentWideTracer<PackedView>::registers;
  return tracer;
}

// One scene's trees, each built once whichever tracers ask: chapter 07's binary trees the
// collapses start from, and the wide4 packed tree that its traversal variants share.
class SceneTrees {
public:
  SceneTrees(const TracerScene& scene, const BuildSink& on_build)
      : scene_(scene), on_build_(on_build) {}

  const ch07::Bvh& binary(Collapse collapse) {
    std::optional<ch07::Bvh>& tree = collapse == Collapse::sah ? sah_ : greedy_;
    if (!tree)
      tree = ch07::build_bvh(scene_.mesh, binary_options(collapse, scene_.bvh.options));
    return *tree;
  }

  // The collapse of the tree `which` reads, the binary build's time included; made once per
  // collapse and width (wide4 and wide4 packed store the same one).
  const WideLayout& layout(ChapterTracer which) {
    const Collapse collapse =
        which == ChapterTracer::cwbvh8_greedy ? Collapse::greedy : Collapse::sah;
    const int width = which == ChapterTracer::wide8 || which == ChapterTracer::cwbvh8 ||
                              which == ChapterTracer::cwbvh8_greedy ||
                              which == ChapterTracer::cpu8
                          ? 8
                          : 4;
    std::optional<WideLayout>& layout = layouts_[collapse == Collapse::sah][width == 8];
    if (!layout) {
      const ch07::Bvh& tree = binary(collapse);
      layout = ch09::collapse(tree, width, collapse);
      layout->stats.build_ms += tree.stats.build_ms;
    }
    return *layout;
  }

  // A stored tree's build, reported under `which`'s name.
  void report(ChapterTracer which, const WideStats& stats) const {
    if (on_build_) on_build_(scene_.name, to_string(which), stats);
  }

  // A stored tree, its build reported.
  template <class Node, class Triangles>
  SharedTree<Node, Triangles> stored(ChapterTracer which, WideTree<Node, Triangles> built) {
    report(which, built.stats);
    return share(std::move(built), scene_);
  }

  const PackedTree& wide4_packed() {
    if (!wide4_packed_)
      wide4_packed_ =
          stored(ChapterTracer::wide4_packed,
                 pack_wide<4, PackedTriangles>(layout(ChapterTracer::wide4_packed)));
    return *wide4_packed_;
  }

private:
  const TracerScene& scene_;
  const BuildSink& on_build_;
  std::optional<ch07::Bvh> sah_, greedy_;
  std::optional<WideLayout> layouts_[2][2]; // [sah][8 wide]
  std::optional<PackedTree> wide4_packed_;
};

// The CPU's own tree as a tracer: a CPU path only, so the runner leaves it out on the GPU.
Tracer cpu_tracer(ChapterTracer which, SceneTrees& trees, const TracerScene& scene) {
  Tracer tracer;
  tracer.name = to_string(which);
  tracer.rule = ch07::HitRule::ties_allowed;
  if (scene.backend == Backend::gpu) return tracer; // no path there: its tree is not built
  const auto tree = std::make_shared<const CpuTree>(pack_cpu(trees.layout(which)));
  trees.report(which, tree->stats);
  tracer.bytes_per_triangle = tree->stats.bytes_per_triangle;
  tracer.trace_cpu = [tree](Query query, std::span<const RayF> rays, std::span<MeshHit> hits) {
    trace_cpu_tree(query, tree->view(), rays, hits);
  };
  tracer.work = [tree](Query query, std::span<const RayF> rays) {
    return measure_cpu_tree_work(query, tree->view(), rays);
  };
  return tracer;
}

Tracer make_wide(ChapterTracer which, SceneTrees& trees, const TracerScene& scene) {
  if (which == ChapterTracer::cpu8) return cpu_tracer(which, trees, scene);
  if (which == ChapterTracer::wide4_packed)
    return wide_tracer(to_string(which), trees.wide4_packed());
  if (is_traversal_variant(which)) return variant_tracer(which, trees.wide4_packed(), scene);
  if (which == ChapterTracer::wide4)
    return wide_tracer(to_string(which),
                       trees.stored(which, pack_wide<4>(trees.layout(which))));
  if (which == ChapterTracer::wide8)
    return wide_tracer(to_string(which),
                       trees.stored(which, pack_wide<8>(trees.layout(which))));
  return wide_tracer(to_string(which), trees.stored(which, compress(trees.layout(which))));
}

} // namespace

const char* to_string(ChapterTracer tracer) { return info(tracer).name; }

Tracer wide4_tracer(std::string name, Wide4PackedBvh tree, const TracerScene& scene) {
  return wide_tracer(std::move(name), share(std::move(tree), scene));
}

bool is_traversal_variant(ChapterTracer tracer) {
  return tracer == ChapterTracer::wide4_packed_shared_stack ||
         tracer == ChapterTracer::wide4_packed_persistent ||
         tracer == ChapterTracer::wide4_packed_sorted ||
         tracer == ChapterTracer::wide4_packed_tiles ||
         tracer == ChapterTracer::wide4_packed_persistent_tiles;
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
    SceneTrees trees(scene, on_build);
    for (const ChapterTracer which : tracers) {
      if (which != ChapterTracer::binary) {
        out.push_back(make_wide(which, trees, scene));
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
  const bool spatial = s.split == ch07::SplitMethod::sbvh;
  const double references_per_triangle =
      s.triangles > 0 ? double(s.references) / double(s.triangles) : 1.0;
  ReportRow row{scene + ", build " + tracer + (spatial ? " from sbvh" : "") + " (CPU)",
                "cpu",
                s.build_ms,
                0.0,
                group_digits(s.nodes) + " nodes, depth " + std::to_string(s.depth) + ", " +
                    format_fixed(s.children_per_node, 1) + " children per node, " +
                    format_fixed(s.triangles_per_leaf, 2) + " triangles per leaf, SAH cost " +
                    format_fixed(s.sah_cost, 1) + ", " + format_fixed(s.bytes_per_triangle, 1) +
                    " B/triangle" +
                    (spatial ? ", " + format_fixed(references_per_triangle, 3) +
                                   " references per triangle"
                             : ""),
                {{"nodes", double(s.nodes)},
                 {"depth", double(s.depth)},
                 {"children_per_node", s.children_per_node},
                 {"triangles_per_leaf", s.triangles_per_leaf},
                 {"sah_cost", s.sah_cost},
                 {"bytes_per_triangle", s.bytes_per_triangle}}};
  // An sbvh tree's bytes per triangle include its extra references: say how many.
  if (spatial) row.metrics.emplace_back("references_per_triangle", references_per_triangle);
  return row;
}

std::string memory_table(const std::vector<ch07::SceneResult>& results) {
  std::ostringstream out;
  out << "\nbytes per triangle (nodes and triangle records; in brackets: against "
      << to_string(ChapterTracer::binary) << ")\n\n| scene |";
  std::vector<ChapterTracer> trees;
  for (const ChapterTracer t : k_all_tracers)
    if (!is_traversal_variant(t)) trees.push_back(t);
  for (const ChapterTracer t : trees) out << " " << to_string(t) << " |";
  out << "\n|---|";
  for (std::size_t k = 0; k < trees.size(); ++k) out << "---|";
  out << "\n";
  for (const ch07::SceneResult& r : results) {
    const ch07::TracerFigure* binary =
        r.find(to_string(ChapterTracer::binary), ch07::RayType::primary);
    out << "| " << r.scene << " |";
    for (const ChapterTracer t : trees) {
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
