// Chapter 11: progressive path tracing. By default it renders the course's Cornell room (or
// any OBJ file with --scene, its MTL's Kd and Ke as albedo and emission) with next-event
// estimation and MIS, and reports each variant's time per sample: the megakernel specialised
// on the scene's features, the all-features megakernel, the persistent threads (the default for
// the image and the window: the GPU's fastest) and the wavefront stages. --output x.png is the
// tone-mapped picture, x.pfm and x.exr the mean radiance itself. Other modes:
//   --window          progressive display; moving the camera starts the sums again
//   --moving          chapter 10's moving scene (or --scene's model waving), moved and its
//                     tree built on the backend every frame, one sample per pixel each
//   --convergence     error against run time at 1, 2, 4, ... --spp samples per pixel, against
//                     a float64 reference of --reference-spp samples, for every strategy
//                     (with --samplers, for every sampler)
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "animation.h"
#include "camera_cli.h"
#include "moving_path.h"
#include "path_render.h"
#include "path_report.h"
#include "program.h"
#include "progressive_program.h"
#include "protocol.h"
#include "rt/image.h"
#include "rt/program_output.h"

namespace {

using namespace rt;
using namespace rt::ch11;

struct ChapterOptions : ch03::ProgramOptions {
  std::string scene_path;
  int spp = 64;
  double seconds = 0.0; // > 0: as many samples as fit in this time, instead of --spp
  bool convergence = false;
  bool samplers = false; // --convergence compares the samplers
  int reference_spp = 1024;
  // The GPU's fastest variant, and the sampler with the least error for its time (book 11b).
  RenderSettings settings{.variant = PathVariant::persistent, .sampler = SamplerKind::sobol};
  double exposure = 1.0;
  double sky = -1.0; // grey sky radiance; < 0: 1 for a scene without emitters, else none
  std::optional<Vec3d> sun;
  double sun_irradiance = 3.0;
  bool moving = false; // chapter 10's moving scene, moved on the backend every frame
  int detail = 316;    // its torus's segments around
  std::shared_ptr<const ch04::Mesh> model; // --moving --scene: fitted, in the torus's place
  bool up_given = false;
};

// --sun's direction as a unit vector. Scaled by its largest component first, in double, so
// that 1e300,1,0 (whose squares overflow) and 1e-300,1e-300,0 (whose squares are zero) are
// directions like any other; zero and numbers that are not finite are refused.
Vec3f sun_direction(Vec3d v) {
  const bool finite = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  const double largest = finite ? max_component(elementwise_abs(v)) : 0.0;
  if (!(largest > 0.0)) {
    std::ostringstream text;
    text << "--sun " << v.x << ',' << v.y << ',' << v.z
         << ": a direction needs three finite numbers, not all zero";
    throw UsageError(text.str());
  }
  return normalize(v / largest).as<float>();
}

// The course's Cornell room, however its path is written: it is seen from its own camera.
bool is_course_room(const std::string& path) {
  std::error_code error;
  return std::filesystem::equivalent(path, RT_ASSETS_DIR "/cornell_room.obj.gz", error);
}

// The scene, its sky and sun, and the camera: the room's own view, or the framing from
// outside (frame_from_outside).
PathScene load_scene(const ChapterOptions& options, CameraSpec& camera) {
  long long defaulted = 0;
  PathScene scene = options.moving ? moving_path_scene(0.0, options.detail, options.model.get())
                                   : load_path_scene(options.scene_path, &defaulted);
  for (const std::string& warning : scene.warnings) warn(warning);
  if (defaulted > 0)
    scene.description += ", " + group_digits(defaulted) +
                         (defaulted == 1 ? " triangle" : " triangles") +
                         " without a material (grey, albedo 0.8)";
  Environment& e = scene.environment;
  const float sky = options.sky >= 0.0 ? float(options.sky) : scene.lights.power > 0 ? 0 : 1;
  e.sky = {sky, sky, sky};
  if (options.sun) {
    e.sun_direction = sun_direction(*options.sun);
    const float s = float(options.sun_irradiance);
    e.sun_irradiance = {s, s * 0.95f, s * 0.85f};
  }
  // Refused before the work: a scene that nothing lights renders black, whatever it holds.
  if (features_used(scene) == 0)
    throw UsageError(std::string("nothing lights the scene: ") +
                     (options.moving ? "chapter 10's moving scene" : options.scene_path) +
                     " has no emitters (MTL Ke), --sky is 0 and there is no sun (--sun with "
                     "an irradiance above 0); every pixel would be black");
  // The room has its own view; the benchmark's interiors (conference, sponza) the protocol's
  // view from inside, so that the figures compare with chapters 07 to 10; other models are
  // framed from outside.
  const bool room = !options.moving && is_course_room(options.scene_path);
  const std::optional<ch07::ProtocolView> interior =
      options.moving ? std::nullopt : ch07::interior_view(options.scene_path);
  CameraSpec framed =
      frame_from_outside(scene.mesh, camera.fov_degrees, options.common.extent());
  if (room) framed = ch11::cornell_camera();
  if (options.moving) framed = ch10::moving_scene_camera();
  if (interior)
    framed = {.eye = interior->eye.as<double>(),
              .target = interior->target.as<double>(),
              .fov_degrees = interior->vfov_degrees};
  if (!options.eye_given) camera.eye = framed.eye;
  if (!options.target_given) camera.target = framed.target;
  if (!options.eye_given && !options.target_given && !options.up_given) camera.up = framed.up;
  if ((room || options.moving || interior.has_value()) && !options.fov_given)
    camera.fov_degrees = framed.fov_degrees;
  return scene;
}

// One line when the whole image came back black: no path found any light.
void warn_if_black(const PathRenderer& renderer) {
  for (const float4& s : renderer.sums())
    if (s.x != 0.0f || s.y != 0.0f || s.z != 0.0f) return;
  warn("every pixel is black: no path reached an emitter, the sky or the sun; is the camera "
       "outside a closed model (--eye, --target), or every light shut away from what it sees?");
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  if (options.sun) sun_direction(*options.sun); // refused before the scene is loaded
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  CameraSpec camera = options.camera;
  const PathScene scene = load_scene(options, camera);
  ch03::validate_camera(camera);
  if (options.convergence) {
    PathRenderer renderer(scene, backend);
    const auto report = options.samplers ? sampler_convergence_report : convergence_report;
    finish_report(report(renderer,
                         options.samplers ? "Chapter 11: error against run time, by sampler"
                                          : "Chapter 11: error against run time",
                         scene.description, camera, options.common.extent(), options.spp,
                         options.reference_spp),
                  options.common);
    return 0;
  }
  // The image's sampler spreads its --spp samples evenly (a --seconds render: blocks of 16).
  options.settings.sampler_samples = options.seconds > 0.0 ? 0 : options.spp;

  Report report = start_report("Chapter 11: progressive path tracing", "Mpaths/s",
                               "the first row's sums after the same samples", backend);
  // Made for the first frame: a moving scene's renderer keeps its scene on the backend and
  // moves it there (moving_path.h).
  std::unique_ptr<PathRenderer> renderer;
  MovingPathRenderer* moving = nullptr; // the same renderer, with --moving
  ShownView shown;
  const auto renderer_for = [&](Backend b) -> PathRenderer& {
    if (!renderer && options.moving) {
      auto made =
          std::make_unique<MovingPathRenderer>(scene, b, options.detail, options.model.get());
      moving = made.get();
      renderer = std::move(made);
    }
    if (!renderer) renderer = std::make_unique<PathRenderer>(scene, b);
    return *renderer;
  };
  // The headless image's samples, for the PNG or the linear file.
  const auto render_image = [&]() -> PathRenderer& {
    PathRenderer& r = renderer_for(backend);
    if (moving) // the animation's last frame
      moving->move_to((moving_frame_count(options.common.frames) - 1) *
                      ch10::k_seconds_per_frame);
    r.restart(camera, options.common.extent());
    const SamplesTaken taken =
        add_image_samples(r, options.settings, options.spp, options.seconds);
    if (options.seconds > 0.0) {
      const std::string text = group_digits(taken.samples) + " samples per pixel in " +
                               format_fixed(taken.seconds, 1) + " s (--seconds)";
      std::cout << "rendered " << text << "\n";
      report.add_context("image samples", text);
    }
    if (r.non_finite() > 0) std::cout << r.non_finite() << " NaN/Inf samples dropped\n";
    warn_if_black(r);
    return r;
  };
  int frame = 0; // the moving scene's, in the window
  const ch03::ProgramParts parts{
      .chapter = "ch11",
      .window_title = "progressive path tracing",
      .camera = camera,
      .render =
          [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
            PathRenderer& r = renderer_for(b);
            if (moving) { // the scene moved on the backend: a new tree, the sums start again
              moving->move_to(frame++ * ch10::k_seconds_per_frame);
              shown.reset();
            }
            add_window_frame(r, shown, spec, extent, options.settings, float(options.exposure),
                             pixels);
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
            PathRenderer& r = renderer_for(backend); // and, with --moving, `moving` set
            if (moving)
              add_moving_rows(*moving, options.settings, camera, options.common.extent(),
                              options.common.frames, rows);
            else
              add_kernel_rows(r, options.settings, camera, options.common.extent(),
                              options.common.frames, rows);
          },
      .image = [&] { return render_image().image(float(options.exposure)); },
      .linear_image =
          [&] {
            const PathRenderer& r = render_image();
            return LinearImage{r.extent().width, r.extent().height, r.mean_radiance()};
          },
      .image_note = "mean of the samples",
  };
  return ch03::run_window_or_headless(options, backend, parts, report);
}

// Flags the run would not read, refused in one line rather than ignored.
void refuse_ignored_flags(const CLI::App& app, const ChapterOptions& options) {
  const auto given = [&](const char* flag) { return app.count(flag) > 0; };
  if (options.moving && options.convergence)
    throw UsageError("--moving renders frames of a moving scene: not with --convergence");
  if (!options.moving && given("--detail")) throw UsageError("--detail goes with --moving");
  if (options.moving && given("--scene") && given("--detail"))
    throw UsageError("--detail sizes the torus: not with --scene, whose model takes its place");
  if (given("--sun-irradiance") && !options.sun)
    throw UsageError("--sun-irradiance is the sun's: give --sun too");
  refuse_progressive_flags(app, options, options.convergence);
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
  app.add_option("--scene", options.scene_path,
                 "OBJ file (its MTL's Kd: albedo in [0, 1], Ke: emission up to 1e6)")
      ->check(CLI::ExistingFile);
  app.add_option("--spp", options.spp,
                 "Samples per pixel of the image (--convergence: the most)")
      ->check(CLI::Range(1, k_max_samples_per_pixel))
      ->capture_default_str();
  app.add_option("--seconds", options.seconds,
                 "Render for this long instead of --spp (at most " +
                     std::to_string(k_max_samples_per_pixel) + " samples per pixel)")
      ->check(finite_range(0.001, 86400.0));
  app.add_flag("--convergence", options.convergence,
               "Error against run time of every strategy, against a float64 reference");
  app.add_option("--reference-spp", options.reference_spp, "Samples of the reference")
      ->check(CLI::Range(1, k_max_samples_per_pixel))
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
  add_sampler_options(app, options.settings, options.samplers);
  app.add_option("--exposure", options.exposure,
                 "Radiance scale before the tone curve (the PNG and the window)")
      ->check(finite_range(1e-6, 1e6))
      ->capture_default_str();
  app.add_option("--sky", options.sky,
                 "Grey sky radiance (default: 1 without emitters, else 0)")
      ->check(finite_range(0.0, k_max_light));
  app.add_option_function<std::vector<double>>(
         "--sun",
         [&](const std::vector<double>& v) {
           options.sun = Vec3d{v[0], v[1], v[2]};
         },
         "Direction towards a sun light, x,y,z (finite, not all zero)")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--sun-irradiance", options.sun_irradiance, "The sun's irradiance")
      ->check(finite_range(0.0, k_max_light))
      ->capture_default_str();
  app.add_flag("--moving", options.moving,
               "Chapter 10's moving scene, moved on the backend every frame (its vertices, "
               "chapter 10's LBVH and collapse) and the sums started again; with --scene, "
               "that model waving in the torus's place; headless, --frames frames of it, the "
               "image the last one's");
  app.add_option("--detail", options.detail,
                 "With --moving: the torus's segments around (detail^2 triangles, at most " +
                     std::to_string(ch10::k_max_moving_detail) + ": 10 million triangles)")
      ->check(CLI::Range(8, ch10::k_max_moving_detail))
      ->capture_default_str();
  ch03::add_image_only_option(app, options);
  add_help_paragraph(app, "Images: --output x.png writes the tone-mapped picture (--exposure "
                          "scales it); x.pfm and x.exr the mean radiance of the samples, "
                          "linear 32-bit floats, neither scaled nor clipped.");
  return ch03::run_program_main(app, argc, argv, options, [&] {
    options.up_given = app.count("--up") > 0;
    refuse_ignored_flags(app, options);
    if (options.moving && app.count("--scene") > 0) // as chapter 10's --moving --scene
      options.model = std::make_shared<const ch04::Mesh>(
          ch10::fit_moving_model(ch05::load_obj(options.scene_path).geometry));
    return run(options);
  });
}
