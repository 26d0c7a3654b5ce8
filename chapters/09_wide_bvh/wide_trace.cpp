// Chapter 09: rays through a wide tree on CPU threads. See wide_trace.h.
#include "wide_trace.h"

#include <algorithm>
#include <vector>

#include "rt/error.h"
#include "wide_traverse.h"

namespace rt::ch09 {
namespace {

// One ray, its triangle test compiled for its own axis permutation: the watertight test's
// largest direction component (kz) and the order of the other two, six cases in all.
template <Query kQuery, class View> TraceHit trace_one(const View& tree, const RayF& ray) {
  const ch04::WatertightRay<float> frame = ch04::watertight_ray(ray);
  return ch04::with_fixed_axes(frame, [&]<class Axes>(Axes) {
    return trace_wide<kQuery>(tree, ray, ch07::NoCounters{}, FramedWatertightTest<Axes>(frame));
  });
}

template <class View> TraceHit trace_one(Query query, const View& tree, const RayF& ray) {
  return query == Query::closest ? trace_one<Query::closest>(tree, ray)
                                 : trace_one<Query::any>(tree, ray);
}

} // namespace

template <class View>
void trace_wide_cpu(Query query, const View& tree, std::span<const RayF> rays,
                    std::span<MeshHit> hits) {
  if (hits.size() != rays.size()) throw Error("trace_wide_cpu: one hit per ray");
  ch07::for_each_ray_cpu(rays.size(), [&](std::size_t i) {
    const TraceHit hit = trace_one(query, tree, rays[i]);
    hits[i] = {hit.t, hit.triangle};
  });
}

template <class View>
void trace_wide_sorted_cpu(Query query, const View& tree, const RaySortFrame& frame,
                           std::span<const RayF> rays, std::span<MeshHit> hits) {
  if (hits.size() != rays.size()) throw Error("trace_wide_sorted_cpu: one hit per ray");
  const std::vector<int> order = sorted_ray_order(rays, frame);
  ch07::for_each_ray_cpu(rays.size(), [&](std::size_t j) {
    const int i = order[j];
    const TraceHit hit = trace_one(query, tree, rays[i]);
    hits[i] = {hit.t, hit.triangle};
  });
}

template <class View>
ch07::TraversalWork measure_wide_work(Query query, const View& tree,
                                      std::span<const RayF> rays) {
  return ch07::average_work(rays, [&](const RayF& ray, ch07::Counters& c) {
    if (query == Query::closest)
      trace_wide<Query::closest>(tree, ray, c);
    else
      trace_wide<Query::any>(tree, ray, c);
  });
}

#define RT_CH09_CPU_LAYOUT(View)                                                               \
  template void trace_wide_cpu<View>(Query, const View&, std::span<const RayF>,                \
                                     std::span<MeshHit>);                                      \
  template ch07::TraversalWork measure_wide_work<View>(Query, const View&,                     \
                                                       std::span<const RayF>);
RT_CH09_CPU_LAYOUT(Wide4Bvh::View)
RT_CH09_CPU_LAYOUT(Wide8Bvh::View)
RT_CH09_CPU_LAYOUT(CompressedBvh::View)
RT_CH09_CPU_LAYOUT(Wide4PackedBvh::View)
#undef RT_CH09_CPU_LAYOUT
template void trace_wide_sorted_cpu<Wide4PackedBvh::View>(Query, const Wide4PackedBvh::View&,
                                                          const RaySortFrame&,
                                                          std::span<const RayF>,
                                                          std::span<MeshHit>);

} // namespace rt::ch09
