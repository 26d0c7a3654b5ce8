// Chapter 11: progressive path tracing. By default it renders the course's Cornell room (or
// any OBJ file with --scene, its MTL's Kd and Ke as albedo and emission) with next-event
// estimation and MIS, and reports each variant's time per sample: the megakernel specialised
// on the scene's features, the all-features megakernel, the persistent threads (the default for
// the image and the window: the GPU's fastest) and the wavefront stages. Other modes:
//   --window          progressive display; moving the camera starts the sums again
//   --convergence     error against run time at 1, 2, 4, ... --spp samples per pixel, against
//                     a float64 reference of --reference-spp samples, for every strategy
#include <chrono>
#include <iostream>
#include <optional>

#include "animation.h"
#include "camera_cli.h"
#include "path_render.h"
#include "path_report.h"
#include "program.h"
#include "protocol.h"
#include "rt/image.h"
#include "rt/program_output.h"
#include "shaded_scene.h"

namespace {

using namespace rt;
using namespace rt::ch11;

struct ChapterOptions : ch03::ProgramOptions {
  std::string scene_path;
  int spp = 64;
  double seconds = 0.0; // > 0: as many samples as fit in this time, instead of --spp
  std::string pfm;      // the linear radiance, unless empty
  bool convergence = false;
  int reference_spp = 1024;
  RenderSettings settings{.variant = PathVariant::persistent}; // the GPU's fastest
  double exposure = 1.0;
  double sky = -1.0; // grey sky radiance; < 0: 1 for a scene without emitters, else none
  std::optional<Vec3d> sun;
  double sun_irradiance = 3.0;
  bool moving = false; // chapter 10's moving scene, its tree built again every frame
  int detail = 316;    // its torus's segments around
};

// The scene, its sky and sun, and the camera: the room's own view, or chapter 06's framing.
PathScene load_scene(const ChapterOptions& options, CameraSpec& camera) {
  long long defaulted = 0;
  PathScene scene = options.moving ? moving_path_scene(0.0, options.detail)
                                   : load_path_scene(options.scene_path, &defaulted);
  if (defaulted > 0)
    scene.description += ", " + group_digits(defaulted) +
                         (defaulted == 1 ? " triangle" : " triangles") +
                         " without a material (grey, albedo 0.8)";
  Environment& e = scene.environment;
  const float sky = options.sky >= 0.0 ? float(options.sky) : scene.lights.power > 0 ? 0 : 1;
  e.sky = {sky, sky, sky};
  if (options.sun) {
    e.sun_direction = normalize(options.sun->as<float>());
    const float s = float(options.sun_irradiance);
    e.sun_irradiance = {s, s * 0.95f, s * 0.85f};
  }
  // The room has its own view; the benchmark's interiors (conference, sponza) the protocol's
  // view from inside, so that the figures compare with chapters 07 to 10; other models are
  // framed from outside.
  const bool room = options.scene_path == RT_ASSETS_DIR "/cornell_room.obj.gz";
  const std::optional<ch07::ProtocolView> interior = ch07::interior_view(options.scene_path);
  CameraSpec framed = ch06::frame_bounds_down_z(ch06::bounds_of(scene.mesh), camera.fov_degrees,
                                                options.common.extent());
  if (room) framed = ch11::cornell_camera();
  if (options.moving) framed = ch10::moving_scene_camera();
  if (interior)
    framed = {.eye = interior->eye.as<double>(),
              .target = interior->target.as<double>(),
              .fov_degrees = interior->vfov_degrees};
  if (!options.eye_given) camera.eye = framed.eye;
  if (!options.target_given) camera.target = framed.target;
  if ((room || options.moving || interior.has_value()) && !options.fov_given)
    camera.fov_degrees = framed.fov_degrees;
  return scene;
}

// --spp samples, or as many as --seconds allows, into the renderer's sums.
void render_final(PathRenderer& renderer, const ChapterOptions& options) {
  if (options.seconds <= 0.0) return renderer.add_samples(options.settings, options.spp);
  const auto end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(options.seconds);
  do {
    renderer.add_samples(options.settings, 1);
    renderer.synchronize();
  } while (std::chrono::steady_clock::now() < end);
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  CameraSpec camera = options.camera;
  const PathScene scene = load_scene(options, camera);
  ch03::validate_camera(camera);
  if (options.convergence) {
    finish_report(convergence_report(scene, backend, camera, options.common.extent(),
                                     options.spp, options.reference_spp),
                  options.common);
    return 0;
  }

  Report report = start_report("Chapter 11: progressive path tracing", "Mpaths/s",
                               "the first row's sums after the same samples", backend);
  std::optional<PathRenderer> renderer; // made for the first frame
  std::optional<std::pair<CameraSpec, Extent>> shown;
  const auto renderer_for = [&](Backend b) -> PathRenderer& {
    if (!renderer)
      renderer.emplace(scene, b, options.moving ? TreeBuild::lbvh : TreeBuild::sah);
    return *renderer;
  };
  int frame = 0; // the moving scene's, in the window
  const ch03::ProgramParts parts{
      .chapter = "ch11",
      .window_title = "progressive path tracing",
      .camera = camera,
      .render =
          [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
            PathRenderer& r = renderer_for(b);
            if (options.moving) { // the scene moved: a new tree, the sums start again
              r.move_vertices(
                  moving_path_scene(frame++ * ch10::k_seconds_per_frame, options.detail)
                      .mesh.vertices);
              shown.reset();
            }
            const bool same =
                shown && shown->second.width == extent.width &&
                shown->second.height == extent.height && shown->first.eye == spec.eye &&
                shown->first.target == spec.target && shown->first.up == spec.up &&
                shown->first.fov_degrees == spec.fov_degrees;
            if (!same) r.restart(spec, extent);
            shown = {spec, extent};
            r.add_samples(options.settings, 1);
            r.tone_map_into(pixels, float(options.exposure));
          },
      .window_row =
          [&](const ch03::WindowResult& seen) {
            return ch03::window_fps_row(describe(options.settings), backend, seen);
          },
      .measure =
          [&](Report& rows) {
            rows.add_context(
                "scene", scene.description + ", " +
                             group_digits(std::ssize(scene.mesh.triangles)) + " triangles, " +
                             group_digits(std::ssize(scene.lights.triangles)) + " emitting");
            rows.add_context("features", describe_path_features(features_used(scene)));
            if (options.moving)
              add_moving_rows(renderer_for(backend), options.settings, options.detail, camera,
                              options.common.extent(), options.common.frames, rows);
            else
              add_kernel_rows(renderer_for(backend), options.settings.strategy, camera,
                              options.common.extent(), options.common.frames, rows);
          },
      .image =
          [&] {
            PathRenderer& r = renderer_for(backend);
            if (options.moving) // the animation's last frame
              r.move_vertices(
                  moving_path_scene((moving_frame_count(options.common.frames) - 1) *
                                        ch10::k_seconds_per_frame,
                                    options.detail)
                      .mesh.vertices);
            r.restart(camera, options.common.extent());
            render_final(r, options);
            if (r.non_finite() > 0) std::cout << r.non_finite() << " NaN/Inf samples dropped\n";
            if (!options.pfm.empty())
              write_pfm(options.pfm, r.extent().width, r.extent().height, r.mean_radiance());
            return r.image(float(options.exposure));
          },
      .image_note = "tone-mapped mean of the samples",
  };
  return ch03::run_window_or_headless(options, backend, parts, report);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 11: progressive path tracing with next-event estimation and MIS",
               "ch11_path_tracing"};
  ChapterOptions options;
  options.common.width = 640;
  options.common.height = 480;
  options.common.output = "ch11_path_tracing.png";
  options.scene_path = RT_ASSETS_DIR "/cornell_room.obj.gz";
  ch03::add_program_options(app, options);
  app.add_option("--scene", options.scene_path, "OBJ file (its MTL's Kd: albedo, Ke: emission)")
      ->check(CLI::ExistingFile);
  app.add_option("--spp", options.spp,
                 "Samples per pixel of the image (--convergence: the most)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  app.add_option("--seconds", options.seconds, "Render for this long instead of --spp")
      ->check(finite_range(0.001, 86400.0));
  app.add_option("--pfm", options.pfm, "Write the linear mean radiance as PFM");
  app.add_flag("--convergence", options.convergence,
               "Error against run time of every strategy, against a float64 reference");
  app.add_option("--reference-spp", options.reference_spp, "Samples of the reference")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--variant",
         [&](const std::string& t) { options.settings.variant = parse_variant(t); },
         "megakernel, persistent or wavefront (the image and the window)")
      ->default_str("persistent");
  app.add_option_function<std::string>(
         "--strategy",
         [&](const std::string& t) { options.settings.strategy = parse_strategy(t); },
         "Direct light by bsdf (bounces only), light (shadow rays only) or mis (both)")
      ->default_str("mis");
  app.add_option("--exposure", options.exposure, "Radiance scale before the tone curve")
      ->check(finite_range(1e-6, 1e6))
      ->capture_default_str();
  app.add_option("--sky", options.sky,
                 "Grey sky radiance (default: 1 without emitters, else 0)")
      ->check(finite_range(0.0, 1e6));
  app.add_option_function<std::vector<double>>(
         "--sun",
         [&](const std::vector<double>& v) {
           options.sun = Vec3d{v[0], v[1], v[2]};
         },
         "Direction towards a sun light, x,y,z")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--sun-irradiance", options.sun_irradiance, "The sun's irradiance")
      ->check(finite_range(0.0, 1e6))
      ->capture_default_str();
  app.add_flag(
      "--moving", options.moving,
      "Chapter 10's moving scene instead of --scene, its tree built on the backend for "
      "every frame (chapter 10's LBVH and collapse) and the sums started again; "
      "headless, --frames frames of it, the image the last one's");
  app.add_option("--detail", options.detail,
                 "With --moving: the torus's segments around (detail^2 triangles)")
      ->check(CLI::Range(8, 4096))
      ->capture_default_str();
  ch03::add_image_only_option(app, options);
  return ch03::run_program_main(app, argc, argv, options, [&] {
    if (options.moving && (app.count("--scene") > 0 || options.convergence))
      throw UsageError(
          "--moving renders chapter 10's scene: not with --scene or --convergence");
    if (!options.moving && app.count("--detail") > 0)
      throw UsageError("--detail goes with --moving");
    return run(options);
  });
}
