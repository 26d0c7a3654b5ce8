// Chapter 09: rays through the CPU's own tree on CPU threads. See cpu_tree.h.
#include "cpu_traverse.h"
#include "rt/error.h"

namespace rt::ch09 {
namespace {

// One ray, its triangle test compiled for its own axis permutation, as trace_wide_cpu does.
template <Query kQuery> TraceHit trace_one(const CpuTreeView& tree, const RayF& ray) {
  const ch04::WatertightRay<float> frame = ch04::watertight_ray(ray);
  return ch04::with_fixed_axes(frame, [&]<class Axes>(Axes) {
    return trace_cpu<kQuery>(tree, ray, ch07::NoCounters{}, FramedWatertightTest<Axes>(frame));
  });
}

} // namespace

void trace_cpu_tree(Query query, const CpuTreeView& tree, std::span<const RayF> rays,
                    std::span<MeshHit> hits) {
  if (hits.size() != rays.size()) throw Error("trace_cpu_tree: one hit per ray");
  ch07::for_each_ray_cpu(rays.size(), [&](std::size_t i) {
    const TraceHit hit = query == Query::closest ? trace_one<Query::closest>(tree, rays[i])
                                                 : trace_one<Query::any>(tree, rays[i]);
    hits[i] = {hit.t, hit.triangle};
  });
}

ch07::TraversalWork measure_cpu_tree_work(Query query, const CpuTreeView& tree,
                                          std::span<const RayF> rays) {
  return ch07::average_work(rays, [&](const RayF& ray, ch07::Counters& c) {
    if (query == Query::closest)
      trace_cpu<Query::closest>(tree, ray, c);
    else
      trace_cpu<Query::any>(tree, ray, c);
  });
}

} // namespace rt::ch09
