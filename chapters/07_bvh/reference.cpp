// Chapter 07: the float64 reference on sampled rays. See reference.h.
#include "reference.h"

#include <algorithm>
#include <cmath>

#include "bvh_trace.h"
#include "rt/cpu_progress.h"

namespace rt::ch07 {

Reference trace_reference(const ch04::Mesh& mesh, std::span<const ch03::RayF> rays,
                          long long count) {
  Reference ref{every_kth_index(rays.size(), count), {}};
  ref.hits.resize(ref.index.size());
  const ch04::MeshView view = ch04::host_view(mesh);
  // Every ray against every triangle, in double: on a large model this takes the CPU long
  // enough to need its progress lines.
  const CpuWorkName name("float64 reference");
  for_each_ray_cpu(ref.index.size(), [&](std::size_t k) {
    ref.hits[k] = ch06::closest_surface(view, ch03::ray_as<double>(rays[ref.index[k]]));
  });
  return ref;
}

std::string error_against(const Reference& ref, std::span<const ch04::MeshHit> hits,
                          ReportRow& row) {
  long long differ = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < ref.index.size(); ++k) {
    const ch04::MeshHit h = hits[ref.index[k]];
    const ch06::SurfaceHit<double>& r = ref.hits[k];
    if (h.triangle != r.triangle) {
      ++differ;
    } else if (r.triangle >= 0) {
      worst = std::max(worst, std::abs(double(h.t) - r.t) / r.t);
    }
  }
  row.metrics.emplace_back("reference_ids_differing", double(differ));
  row.metrics.emplace_back("max_rel_t_error", worst);
  return group_digits(differ) + " of " +
         group_digits(static_cast<long long>(ref.index.size())) +
         " ids differ from float64, max rel t err " + format_scientific(worst);
}

} // namespace rt::ch07
