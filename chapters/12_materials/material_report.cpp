// Chapter 12: the program's rows. See material_report.h.
#include "material_report.h"

#include <cmath>
#include <tuple>

#include "rt/program_output.h"
#include "rt/timer.h"

namespace rt::ch12 {

double rms_difference(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec3d d = (a[i] - b[i]).as<double>();
    sum += d.x * d.x + d.y * d.y + d.z * d.z;
  }
  return a.empty() ? 0.0 : std::sqrt(sum / (3.0 * double(a.size())));
}

namespace {

// Milliseconds per sample per pixel of `settings` on `renderer`, and its Mrays/s given the
// rays a path traces.
struct SampleTime {
  double ms = 0.0;
  double rays_per_path = 0.0;
  double mrays(Extent extent) const {
    return double(extent.pixel_count()) * rays_per_path / (ms * 1e3);
  }
};

SampleTime time_samples(ch11::ProgressiveRenderer& renderer, const RenderSettings& settings,
                        const CameraSpec& camera, Extent extent, int frames) {
  renderer.restart(camera, extent);
  const ch11::RayCounts rays = renderer.add_counted_sample(settings.strategy);
  renderer.restart(camera, extent);
  const Timing t = time_on(
      renderer.backend(), [&] { renderer.add_samples(settings, 1); }, frames);
  return {t.median_ms, double(rays.total()) / double(extent.pixel_count())};
}

} // namespace

void add_material_rows(MaterialRenderer& renderer, const MaterialScene& scene,
                       const RenderSettings& settings, const CameraSpec& camera, Extent extent,
                       int frames, Report& report) {
  const Backend backend = renderer.backend();
  const MaterialOptions kept = renderer.options();
  const SampleTime ours = time_samples(renderer, settings, camera, extent, frames);
  {
    ch11::PathRenderer lambertian(scene.path, backend);
    const SampleTime theirs = time_samples(lambertian, settings, camera, extent, frames);
    const double ratio = ours.mrays(extent) / theirs.mrays(extent);
    report.add_row({"chapter 11's tracer, same geometry (Lambertian, no textures)",
                    to_string(backend),
                    theirs.ms,
                    double(extent.pixel_count()) / (theirs.ms * 1e3),
                    format_fixed(theirs.mrays(extent), 1) + " Mrays/s (" +
                        format_fixed(theirs.rays_per_path, 2) +
                        " rays per path); chapter 12's " + format_fixed(ours.mrays(extent), 1) +
                        " Mrays/s, " + format_fixed(ratio, 2) + "x",
                    {{"mrays_per_s", theirs.mrays(extent)},
                     {"rays_per_path", theirs.rays_per_path},
                     {"chapter12_mrays_per_s", ours.mrays(extent)},
                     {"chapter12_vs_chapter11_mrays", ratio}}});
  }
  const unsigned features = renderer.features();
  if ((features & k_textures) != 0) {
    MaterialOptions reference_options = kept;
    reference_options.filter = TextureFilter::point;
    reference_options.texture_objects = false;
    renderer.set_options(reference_options);
    const std::vector<Vec3f> reference =
        render_base_colour(renderer, camera, extent, k_aliasing_reference_samples);
    for (TextureFilter filter :
         {TextureFilter::point, TextureFilter::bilinear, TextureFilter::trilinear})
      for (bool objects : {true, false}) {
        if (objects && backend != Backend::gpu) continue; // the CPU has no texture units
        MaterialOptions o = kept;
        o.filter = filter;
        o.texture_objects = objects;
        renderer.set_options(o);
        const SampleTime t = time_samples(renderer, settings, camera, extent, frames);
        const double error =
            rms_difference(render_base_colour(renderer, camera, extent, 1), reference);
        report.add_row(
            {std::string("textures: ") + to_string(filter) +
                 (backend == Backend::gpu ? (objects ? ", texture objects" : ", plain loads")
                                          : ""),
             to_string(backend),
             t.ms,
             double(extent.pixel_count()) / (t.ms * 1e3),
             "base colour RMSE " + format_fixed(error, 4) + " against " +
                 std::to_string(k_aliasing_reference_samples) +
                 " jittered samples per pixel (aliasing)",
             {{"aliasing_rmse", error}, {"mrays_per_s", t.mrays(extent)}}});
      }
  }
  if ((features & k_specular) != 0) {
    MaterialOptions o = kept;
    o.compensation = !kept.compensation;
    renderer.set_options(o);
    const SampleTime t = time_samples(renderer, settings, camera, extent, frames);
    report.add_row({std::string("energy compensation ") + (o.compensation ? "on" : "off"),
                    to_string(backend),
                    t.ms,
                    double(extent.pixel_count()) / (t.ms * 1e3),
                    format_fixed(t.ms / ours.ms, 2) + "x the time with it " +
                        (o.compensation ? "off" : "on"),
                    {{"time_vs_default", t.ms / ours.ms}}});
  }
  renderer.set_options(kept);
  // The two visible-normal samplers, alone: 2^24 normals (2^20 on the CPU).
  const int threads = backend == Backend::gpu ? 1 << 18 : 1 << 14;
  const VisibleNormalTiming heitz =
      time_visible_normals(backend, VisibleNormals::heitz, threads, frames);
  const VisibleNormalTiming caps =
      time_visible_normals(backend, VisibleNormals::caps, threads, frames);
  for (const auto& [name, t, other] :
       {std::tuple{"visible normals: Heitz 2018", heitz, caps},
        std::tuple{"visible normals: spherical caps (Dupuy and Benyoub 2023)", caps, heitz}})
    report.add_row({name,
                    to_string(backend),
                    t.ms,
                    double(t.samples) / (t.ms * 1e3),
                    "mean normal z " + format_fixed(t.mean_z, 5) + ", the other sampler's " +
                        format_fixed(other.mean_z, 5) + " (" + group_digits(t.samples) +
                        " normals; throughput in millions of normals per second)",
                    {{"mean_z", t.mean_z}, {"normals", double(t.samples)}}});
}

} // namespace rt::ch12
