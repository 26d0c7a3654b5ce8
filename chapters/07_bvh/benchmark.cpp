// Chapter 07: the benchmark protocol on a list of scenes. See benchmark.h.
#include "benchmark.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "bvh_build.h"
#include "bvh_render.h"
#include "bvh_trace.h"
#include "model_render.h"
#include "obj_loader.h"
#include "protocol.h"
#include "rt/device_buffer.h"
#include "rt/timer.h"
#include "shaded_render.h"
#include "shaded_scene.h"

namespace rt::ch07 {
namespace {

using ch04::MeshHit;

// The elements of `all` at `index`.
template <class T>
std::vector<T> pick(std::span<const T> all, const std::vector<std::size_t>& index) {
  std::vector<T> out;
  out.reserve(index.size());
  for (const std::size_t i : index) out.push_back(all[i]);
  return out;
}

// One batch of rays on one backend: the timed trace, and the sample checked by brute force.
struct TracedBatch {
  std::vector<MeshHit> hits;
  Timing timing;
  HitAgreement check;
  long long sampled = 0; // rays checked
};

TracedBatch trace_batch(const BenchmarkOptions& o, Query query, const Bvh& bvh,
                        const DeviceBvh* d_bvh, const ch04::Mesh& mesh,
                        std::span<const RayF> rays, const RayF* d_rays) {
  TracedBatch out;
  out.hits.resize(rays.size());
  const int count = static_cast<int>(rays.size());
  if (o.backend == Backend::gpu) {
    DeviceBuffer<MeshHit> d_hits(rays.size());
    out.timing = time_on(
        Backend::gpu,
        [&] { trace_rays_gpu(query, o.variant, d_bvh->view(), d_rays, count, d_hits.data()); },
        o.frames);
    d_hits.download(out.hits);
  } else {
    out.timing = time_on(
        Backend::cpu, [&] { trace_rays_cpu(query, o.variant, bvh.view(), rays, out.hits); },
        o.frames);
  }
  // The check: brute force (every triangle) on a sample of the rays, closest hits. An any-hit
  // query is checked for agreeing on hit or miss.
  const std::vector<std::size_t> index = every_kth_index(rays.size(), o.check_rays);
  const std::vector<RayF> sample = pick(rays, index);
  std::vector<MeshHit> tree = pick(std::span<const MeshHit>(out.hits), index);
  std::vector<MeshHit> brute(sample.size());
  if (o.backend == Backend::gpu) {
    const DeviceBuffer<RayF> d_sample{std::span<const RayF>(sample)};
    DeviceBuffer<MeshHit> d_brute(sample.size());
    const DeviceBuffer<Vec3f> d_vertices{std::span<const Vec3f>(mesh.vertices)};
    const DeviceBuffer<ch04::IndexedTriangle> d_triangles{
        std::span<const ch04::IndexedTriangle>(mesh.triangles)};
    brute_force_gpu(o.variant,
                    {d_vertices.data(), d_triangles.data(), int(mesh.triangles.size())},
                    d_sample.data(), int(sample.size()), d_brute.data());
    d_brute.download(brute);
  } else {
    brute = ch04::closest_hits_cpu(o.variant, mesh, sample);
  }
  if (query == Query::any) { // any hit: only "hit or not" must agree
    for (std::size_t i = 0; i < tree.size(); ++i) {
      tree[i] = {0.0f, tree[i].triangle >= 0 ? 0 : -1};
      brute[i] = {0.0f, brute[i].triangle >= 0 ? 0 : -1};
    }
  }
  out.check = compare_hits(tree, brute);
  out.sampled = static_cast<long long>(sample.size());
  return out;
}

ReportRow ray_row(const std::string& scene, RayType type, const BenchmarkOptions& o,
                  const TracedBatch& batch, long long rays, long long pixels) {
  const double mrays = double(rays) / (batch.timing.median_ms * 1e3);
  std::string error = group_digits(batch.check.mismatches) + " of " +
                      group_digits(batch.sampled) + " sampled rays differ from brute force";
  if (batch.check.ties > 0) error += " (" + group_digits(batch.check.ties) + " exact ties)";
  if (type == RayType::primary) {
    const auto hit = std::count_if(batch.hits.begin(), batch.hits.end(),
                                   [](const MeshHit& h) { return h.triangle >= 0; });
    error += "; " + format_fixed(100.0 * double(hit) / double(pixels), 1) + "% of pixels hit";
  }
  return {scene + ", " + to_string(type),
          to_string(o.backend),
          batch.timing.median_ms,
          mrays,
          error,
          {{"rays", double(rays)},
           {"mrays_per_s", mrays},
           {"mismatches", double(batch.check.mismatches)},
           {"ties", double(batch.check.ties)}}};
}

// The end-to-end frame: camera rays, the tree, chapter 06's Lambertian shading with smooth
// normals and a shadow ray per light, and 8-bit pixels written, at the benchmark's size.
Timing time_shaded_frame(const BenchmarkOptions& o, const ch05::ObjMesh& obj, const Bvh& bvh,
                         const DeviceBvh* d_bvh, const PinholeCamera& pinhole,
                         long long& shadow_rays) {
  const ch06::ShadedScene scene = ch06::scene_from_obj(obj, ch06::LightSettings{});
  const unsigned features = ch06::features_used(scene, true, true);
  ch03::Camera<float> camera;
  camera.pinhole = pinhole;
  const Extent extent = o.extent;
  std::vector<ch06::ShadedPixelRecord> records(extent.pixel_count());
  Timing timing;
  if (o.backend == Backend::gpu) {
    const ch06::DeviceShadedScene d_scene(scene, features);
    const BvhSceneView view = with_bvh(d_scene.view(), d_bvh->view());
    DeviceBuffer<Rgba8> d_pixels(extent.pixel_count());
    DeviceBuffer<ch06::ShadedPixelRecord> d_records(extent.pixel_count());
    timing = time_on(
        Backend::gpu,
        [&] {
          render_bvh_shaded(Backend::gpu, features, view, camera, extent, d_pixels.data());
        },
        o.frames);
    render_bvh_shaded(Backend::gpu, features, view, camera, extent, d_pixels.data(),
                      d_records.data());
    d_records.download(records);
  } else {
    const BvhSceneView view = with_bvh(ch06::host_view(scene, features), bvh.view());
    std::vector<Rgba8> pixels(extent.pixel_count());
    timing = time_on(
        Backend::cpu,
        [&] { render_bvh_shaded(Backend::cpu, features, view, camera, extent, pixels.data()); },
        o.frames);
    render_bvh_shaded(Backend::cpu, features, view, camera, extent, pixels.data(),
                      records.data());
  }
  shadow_rays = 0;
  for (const auto& r : records) shadow_rays += r.shadow_rays;
  return timing;
}

} // namespace

ReportRow build_row(const std::string& variant, const Bvh& bvh) {
  const BuildStats& s = bvh.stats;
  const double triangles = double(bvh.triangles.size());
  return {variant,
          "cpu",
          s.build_ms,
          triangles / (s.build_ms * 1e3),
          group_digits(s.nodes) + " nodes, depth " + std::to_string(s.depth) + ", SAH cost " +
              format_fixed(s.sah_cost, 1) + ", " + format_fixed(s.bytes_per_triangle, 1) +
              " B/triangle (Mtriangles/s)",
          {{"triangles", triangles},
           {"nodes", double(s.nodes)},
           {"depth", double(s.depth)},
           {"sah_cost", s.sah_cost},
           {"bytes_per_triangle", s.bytes_per_triangle}}};
}

std::string scene_name(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  for (const std::string suffix : {".gz", ".obj"})
    if (name.size() > suffix.size() && name.ends_with(suffix))
      name.resize(name.size() - suffix.size());
  return name;
}

std::vector<std::string> benchmark_set(const std::string& folder) {
  std::vector<std::string> found;
  for (const char* name : {"stanford-bunny", "armadillo-100k", "stanford-dragon", "conference",
                           "sponza-dabrovic"}) {
    const std::filesystem::path path =
        std::filesystem::path(folder) / (std::string(name) + ".obj.gz");
    std::error_code ignored;
    if (std::filesystem::is_regular_file(path, ignored)) found.push_back(path.string());
  }
  return found;
}

// [listing:benchmark_scene]
std::vector<BenchmarkResult> run_benchmark(const std::vector<std::string>& scenes,
                                           const BenchmarkOptions& o, Report& report) {
  std::vector<BenchmarkResult> results;
  for (const std::string& path : scenes) {
    const std::string name = scene_name(path);
    const ch05::ObjMesh obj = ch05::load_obj(path);
    const ch04::Mesh& mesh = obj.geometry;
    const Bvh bvh = build_bvh(mesh, o.build);
    const ProtocolView view = protocol_view(path, bvh.bounds);
    const PinholeCamera camera = make_protocol_camera(view, o.extent.width, o.extent.height);
    const float radius = scene_radius(bvh.bounds);
    const long long pixels = o.extent.pixel_count();

    std::optional<DeviceBvh> d_bvh;
    std::optional<DeviceBuffer<RayF>> d_rays, d_secondary;
    std::optional<DeviceBuffer<MeshHit>> d_primary;
    std::optional<DeviceBuffer<int>> d_pixels;
    std::optional<DeviceBuffer<Vec3f>> d_vertices;
    std::optional<DeviceBuffer<ch04::IndexedTriangle>> d_triangles;
    std::vector<RayF> rays;
    if (o.backend == Backend::gpu) {
      ch05::check_device_memory(
          bvh.nodes.size() * sizeof(BvhNode) +
              bvh.triangles.size() * (sizeof(TriangleF) + sizeof(int)) +
              mesh.vertices.size() * sizeof(Vec3f) +
              mesh.triangles.size() * sizeof(ch04::IndexedTriangle) +
              std::size_t(pixels) * (2 * sizeof(RayF) + 2 * sizeof(MeshHit) + sizeof(int) + 12),
          name);
      d_bvh.emplace(bvh);
      d_rays.emplace(pixels);
      camera_rays_gpu(camera, d_rays->data());
      rays = d_rays->to_host();
      d_vertices.emplace(std::span<const Vec3f>(mesh.vertices));
      d_triangles.emplace(std::span<const ch04::IndexedTriangle>(mesh.triangles));
    } else {
      rays = camera_rays_cpu(camera);
    }

    // Primary rays: closest hits, every pixel.
    const TracedBatch primary = trace_batch(o, Query::closest, bvh, d_bvh ? &*d_bvh : nullptr,
                                            mesh, rays, d_rays ? d_rays->data() : nullptr);
    report.add_row(ray_row(name, RayType::primary, o, primary, pixels, pixels));
    BenchmarkResult result{name, static_cast<long long>(mesh.triangles.size())};
    result.mrays_primary = double(pixels) / (primary.timing.median_ms * 1e3);
    result.mismatches += primary.check.mismatches;

    // Secondary rays from every primary hit: ao (any hit, short) and diffuse (closest).
    if (o.backend == Backend::gpu) {
      d_primary.emplace(std::span<const MeshHit>(primary.hits));
      d_secondary.emplace(pixels);
      d_pixels.emplace(pixels);
    }
    for (const RayType type : {RayType::ao, RayType::diffuse}) {
      SecondaryRays secondary;
      if (o.backend == Backend::gpu) {
        const int count = secondary_rays_gpu(
            type, {d_vertices->data(), d_triangles->data(), int(mesh.triangles.size())},
            d_primary->data(), camera, radius, d_secondary->data(), d_pixels->data());
        secondary.rays.resize(count);
        if (count > 0)
          RT_CUDA_CHECK(cudaMemcpy(secondary.rays.data(), d_secondary->data(),
                                   count * sizeof(RayF), cudaMemcpyDeviceToHost));
      } else {
        secondary = secondary_rays_cpu(type, mesh, primary.hits, camera, radius);
      }
      const Query query = type == RayType::ao ? Query::any : Query::closest;
      const TracedBatch batch =
          trace_batch(o, query, bvh, d_bvh ? &*d_bvh : nullptr, mesh, secondary.rays,
                      d_secondary ? d_secondary->data() : nullptr);
      const long long count = static_cast<long long>(secondary.rays.size());
      report.add_row(ray_row(name, type, o, batch, count, pixels));
      const double mrays = count > 0 ? double(count) / (batch.timing.median_ms * 1e3) : 0.0;
      (type == RayType::ao ? result.mrays_ao : result.mrays_diffuse) = mrays;
      result.mismatches += batch.check.mismatches;
    }

    result.build_ms = bvh.stats.build_ms;
    result.bytes_per_triangle = bvh.stats.bytes_per_triangle;
    report.add_row(
        build_row(name + ", build (" + std::string(to_string(o.build.method)) + ", CPU)", bvh));

    if (o.end_to_end) {
      long long shadow_rays = 0;
      const Timing frame =
          time_shaded_frame(o, obj, bvh, d_bvh ? &*d_bvh : nullptr, camera, shadow_rays);
      result.frame_ms = frame.median_ms;
      report.add_row(
          {name + ", shaded frame (end to end)",
           to_string(o.backend),
           frame.median_ms,
           double(pixels + shadow_rays) / (frame.median_ms * 1e3),
           format_fixed(1000.0 / frame.median_ms, 1) +
               " frames/s: camera rays, tree, smooth Lambert, " + group_digits(shadow_rays) +
               " shadow rays, 8-bit pixels",
           {{"fps", 1000.0 / frame.median_ms}, {"shadow_rays", double(shadow_rays)}}});
    }
    results.push_back(result);
  }
  return results;
}
// [/listing:benchmark_scene]

namespace {

// OptiX 9.0 on the same GPU (BENCHMARK.md): primary, ao, diffuse Mrays/s at 1920x1080.
struct Anchor {
  const char* scene;
  double primary, ao, diffuse;
};
constexpr Anchor k_optix_h100[] = {{"conference", 3700, 3275, 1326},
                                   {"sponza-dabrovic", 3283, 2535, 1061},
                                   {"stanford-dragon", 5251, 632, 429},
                                   {"stanford-bunny", 8240, 1133, 768}};
constexpr Anchor k_optix_h200[] = {{"conference", 3715, 3299, 1328},
                                   {"sponza-dabrovic", 3300, 2539, 1063},
                                   {"stanford-dragon", 5293, 638, 437},
                                   {"stanford-bunny", 8275, 1138, 795}};

const Anchor* anchor_for(const std::string& scene, const std::string& device) {
  const bool h100 = device.find("H100") != std::string::npos;
  const bool h200 = device.find("H200") != std::string::npos;
  if (!h100 && !h200) return nullptr;
  for (const Anchor& a :
       h100 ? std::span<const Anchor>(k_optix_h100) : std::span<const Anchor>(k_optix_h200))
    if (scene == a.scene) return &a;
  return nullptr;
}

std::string with_share(double ours, const Anchor* a, double Anchor::*field) {
  std::string text = format_fixed(ours, ours < 100 ? 1 : 0);
  if (a != nullptr) text += " (" + format_fixed(100.0 * ours / (a->*field), 0) + "%)";
  return text;
}

} // namespace

std::string summary_table(const std::vector<BenchmarkResult>& results,
                          const std::string& device) {
  std::ostringstream out;
  out << "| scene | triangles | primary | ao | diffuse | build ms | bytes/triangle | frame ms "
         "(fps) |\n|---|---|---|---|---|---|---|---|\n";
  bool any_anchor = false;
  for (const BenchmarkResult& r : results) {
    const Anchor* a = anchor_for(r.scene, device);
    any_anchor = any_anchor || a != nullptr;
    out << "| " << r.scene << " | " << group_digits(r.triangles) << " | "
        << with_share(r.mrays_primary, a, &Anchor::primary) << " | "
        << with_share(r.mrays_ao, a, &Anchor::ao) << " | "
        << with_share(r.mrays_diffuse, a, &Anchor::diffuse) << " | "
        << format_fixed(r.build_ms, 0) << " | " << format_fixed(r.bytes_per_triangle, 0)
        << " | "
        << (r.frame_ms > 0 ? format_fixed(r.frame_ms, 2) + " (" +
                                 format_fixed(1000.0 / r.frame_ms, 0) + ")"
                           : std::string("-"))
        << " |\n";
  }
  out << "Mrays/s on " << device << ", kernel only, median.";
  if (any_anchor) out << " In brackets: share of OptiX 9.0's figure on the same GPU.";
  out << "\n";
  return out.str();
}

} // namespace rt::ch07
