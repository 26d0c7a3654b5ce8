// Chapter 12: materials, textures and glTF scenes. By default it renders the course's material
// room (assets/material_room.gltf: chapter 11's room with a glass sphere, a rough gold one, a
// rough glass one and a textured floor), or any OBJ (with its MTL's PBR fields) or glTF 2.0
// file with --scene, through chapter 11's variants, and reports each variant's time per
// sample, chapter 11's tracer on the same geometry, the texture filters and reads, and the
// energy compensation. --output x.png is the tone-mapped picture, x.pfm and x.exr the mean
// radiance itself. Other modes:
//   --furnace M       a sphere of material M alone under a white sky: invisible if M loses
//                     no energy (--roughness, --no-compensation)
//   --series M        five spheres of M from smooth to rough
//   --convergence     error against run time at 1, 2, 4, ... --spp samples per pixel
//   --window          progressive display; moving the camera starts the sums again
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

#include "camera_cli.h"
#include "material_render.h"
#include "material_report.h"
#include "material_scenes.h"
#include "path_report.h"
#include "program.h"
#include "progressive_program.h"
#include "rt/image.h"
#include "rt/program_output.h"
#include "scene_loaders.h"

namespace {

using namespace rt;
using namespace rt::ch12;

struct ChapterOptions : ch03::ProgramOptions {
  std::string scene_path;
  std::string furnace, series; // a built-in scene's material, or empty
  double roughness = -1.0;     // the material's own
  int spp = 64;
  double seconds = 0.0;
  bool convergence = false;
  bool samplers = false; // --convergence compares the samplers
  int reference_spp = 1024;
  // The GPU's fastest variant here, and chapter 11's sampler with the least error for its time.
  RenderSettings settings{.variant = PathVariant::wavefront,
                          .sampler = ch11::SamplerKind::sobol};
  MaterialOptions materials;
  double exposure = 1.0;
  double sky = -1.0; // < 0: 1 for a scene without emitters, else none
  bool up_given = false;
};

// The course's material room, however its path is written: it is seen from the room's camera.
bool is_course_room(const std::string& path) {
  std::error_code error;
  for (const char* file : {"/material_room.gltf", "/material_room.obj.gz"})
    if (std::filesystem::equivalent(path, std::string(RT_ASSETS_DIR) + file, error))
      return true;
  return false;
}

MaterialScene load_scene(const ChapterOptions& options, CameraSpec& camera) {
  MaterialScene scene;
  CameraSpec framed;
  bool own_view = true; // the scene's own camera (built-in scenes, the room, a glTF camera)
  if (!options.furnace.empty()) {
    scene =
        make_sphere_in_sky(named_material(options.furnace, float(options.roughness)), 5, 1.0f);
    framed = sphere_camera();
  } else if (!options.series.empty()) {
    scene = make_roughness_series(named_material(options.series));
    framed = roughness_series_camera();
  } else {
    scene = load_material_scene(options.scene_path);
    for (const std::string& warning : scene.path.warnings) warn(warning);
    if (scene.camera) {
      framed = *scene.camera;
    } else if (is_course_room(options.scene_path)) {
      framed = ch11::cornell_camera();
    } else {
      framed = ch11::frame_from_outside(scene.path.mesh, camera.fov_degrees,
                                        options.common.extent());
      own_view = false;
    }
  }
  ch11::Environment& e = scene.path.environment;
  if (options.sky >= 0.0 || (options.furnace.empty() && options.series.empty())) {
    const float sky = options.sky >= 0.0            ? float(options.sky)
                      : scene.path.lights.power > 0 ? 0.0f
                                                    : 1.0f;
    e.sky = {sky, sky, sky};
  }
  if ((material_features_used(scene) & ch11::k_all_path_features) == 0)
    throw UsageError("nothing lights the scene: it has no emitters and --sky is 0; every "
                     "pixel would be black");
  if (!options.eye_given) camera.eye = framed.eye;
  if (!options.target_given) camera.target = framed.target;
  if (!options.eye_given && !options.target_given && !options.up_given) camera.up = framed.up;
  if (own_view && !options.fov_given) camera.fov_degrees = framed.fov_degrees;
  return scene;
}

int run(ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  CameraSpec camera = options.camera;
  const MaterialScene scene = load_scene(options, camera);
  ch03::validate_camera(camera);
  if (options.convergence) {
    MaterialRenderer renderer(scene, backend, options.materials);
    const auto report =
        options.samplers ? ch11::sampler_convergence_report : ch11::convergence_report;
    finish_report(report(renderer,
                         options.samplers ? "Chapter 12: error against run time, by sampler"
                                          : "Chapter 12: error against run time",
                         scene.path.description, camera, options.common.extent(), options.spp,
                         options.reference_spp),
                  options.common);
    return 0;
  }
  // The image's sampler spreads its --spp samples evenly (a --seconds render: blocks of 16).
  options.settings.sampler_samples = options.seconds > 0.0 ? 0 : options.spp;
  Report report = start_report("Chapter 12: materials, textures and glTF scenes", "Mpaths/s",
                               "the first row's sums after the same samples", backend);
  std::optional<MaterialRenderer> renderer;
  ch11::ShownView shown;
  const auto renderer_for = [&](Backend b) -> MaterialRenderer& {
    if (!renderer) renderer.emplace(scene, b, options.materials);
    return *renderer;
  };
  const auto render_image = [&]() -> MaterialRenderer& {
    MaterialRenderer& r = renderer_for(backend);
    if (r.options().filter != options.materials.filter ||
        r.options().texture_objects != options.materials.texture_objects ||
        r.options().compensation != options.materials.compensation)
      r.set_options(options.materials); // the measurements tried others
    r.restart(camera, options.common.extent());
    const ch11::SamplesTaken taken =
        ch11::add_image_samples(r, options.settings, options.spp, options.seconds);
    if (options.seconds > 0.0) {
      const std::string text = group_digits(taken.samples) + " samples per pixel in " +
                               format_fixed(taken.seconds, 1) + " s (--seconds)";
      std::cout << "rendered " << text << "\n";
      report.add_context("image samples", text);
    }
    if (r.non_finite() > 0) std::cout << r.non_finite() << " NaN/Inf samples dropped\n";
    return r;
  };
  const ch03::ProgramParts parts{
      .chapter = "ch12",
      .window_title = "materials",
      .camera = camera,
      .render =
          [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
            MaterialRenderer& r = renderer_for(b);
            ch11::add_window_frame(r, shown, spec, extent, options.settings,
                                   float(options.exposure), pixels);
          },
      .window_row =
          [&](const ch03::WindowResult& seen) {
            return ch03::window_fps_row(ch11::describe(options.settings), backend, seen);
          },
      .measure =
          [&](Report& rows) {
            rows.add_context("scene", scene.path.description);
            MaterialRenderer& r = renderer_for(backend);
            ch11::add_kernel_rows(r, options.settings, camera, options.common.extent(),
                                  options.common.frames, rows);
            add_material_rows(r, scene, options.settings, camera, options.common.extent(),
                              options.common.frames, rows);
          },
      .image = [&] { return render_image().image(float(options.exposure)); },
      .linear_image =
          [&] {
            const MaterialRenderer& r = render_image();
            return LinearImage{r.extent().width, r.extent().height, r.mean_radiance()};
          },
      .image_note = "mean of the samples",
  };
  return ch03::run_window_or_headless(options, backend, parts, report);
}

// Flags the run would not read, refused in one line rather than ignored.
void refuse_ignored_flags(const CLI::App& app, const ChapterOptions& options) {
  const auto given = [&](const char* flag) { return app.count(flag) > 0; };
  const int scenes = int(given("--scene")) + int(given("--furnace")) + int(given("--series"));
  if (scenes > 1)
    throw UsageError("--scene, --furnace and --series each choose the scene: one");
  if (given("--roughness") && !given("--furnace"))
    throw UsageError("--roughness is the --furnace sphere's (--series shows five)");
  ch11::refuse_progressive_flags(app, options, options.convergence);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Chapter 12: materials (GGX conductors, dielectrics, glTF's metallic-roughness), "
      "textures and glTF scenes",
      "ch12_materials"};
  ChapterOptions options;
  options.common.width = 640;
  options.common.height = 480;
  options.common.output = "ch12_materials.png";
  options.scene_path = RT_ASSETS_DIR "/material_room.gltf";
  ch03::add_program_options(app, options);
  app.add_option("--scene", options.scene_path,
                 "An OBJ file (.obj, .obj.gz; its MTL's Kd, Pm, Pr, Ni, Tf, illum 7, Ke and "
                 "maps) or a glTF 2.0 file (.gltf, .glb)")
      ->check(CLI::ExistingFile);
  app.add_option("--furnace", options.furnace,
                 "A sphere of this material alone under a white sky (" + material_names() +
                     ")");
  app.add_option("--series", options.series,
                 "Five spheres of this material, roughness 0 to 1 (" + material_names() + ")");
  app.add_option("--roughness", options.roughness,
                 "The --furnace sphere's roughness (default: 0 for glass, 0.3 for the others)")
      ->check(finite_range(0.0, 1.0));
  app.add_option("--spp", options.spp,
                 "Samples per pixel of the image (--convergence: the most)")
      ->check(CLI::Range(1, ch11::k_max_samples_per_pixel))
      ->capture_default_str();
  app.add_option("--seconds", options.seconds,
                 "Render for this long instead of --spp (at most " +
                     std::to_string(ch11::k_max_samples_per_pixel) + " samples per pixel)")
      ->check(finite_range(0.001, 86400.0));
  app.add_flag("--convergence", options.convergence,
               "Error against run time of every strategy, against a float64 reference");
  app.add_option("--reference-spp", options.reference_spp, "Samples of the reference")
      ->check(CLI::Range(1, ch11::k_max_samples_per_pixel))
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--variant",
         [&](const std::string& t) { options.settings.variant = ch11::parse_variant(t); },
         "megakernel, persistent or wavefront (the image and the window)")
      ->default_str("wavefront");
  app.add_option_function<std::string>(
         "--strategy",
         [&](const std::string& t) { options.settings.strategy = ch11::parse_strategy(t); },
         "Direct light by bsdf (bounces only), light (shadow rays only) or mis (both)")
      ->default_str("mis");
  ch11::add_sampler_options(app, options.settings, options.samplers);
  app.add_option_function<std::string>(
         "--filter",
         [&](const std::string& t) { options.materials.filter = parse_texture_filter(t); },
         "Texture filter: point, bilinear or trilinear (mipmapped, by ray cones)")
      ->default_str("trilinear");
  app.add_flag_function(
      "--plain-loads", [&](std::int64_t) { options.materials.texture_objects = false; },
      "GPU: read textures with plain loads and the software filter, not texture objects");
  app.add_flag_function(
      "--no-compensation", [&](std::int64_t) { options.materials.compensation = false; },
      "Leave out the energy compensation of rough metals and glass (their loss shows)");
  app.add_option("--exposure", options.exposure,
                 "Radiance scale before the tone curve (the PNG and the window)")
      ->check(finite_range(1e-6, 1e6))
      ->capture_default_str();
  app.add_option("--sky", options.sky,
                 "Grey sky radiance (default: 1 without emitters, else 0)")
      ->check(finite_range(0.0, ch11::k_max_light));
  ch03::add_image_only_option(app, options);
  add_help_paragraph(app, "Images: --output x.png writes the tone-mapped picture (--exposure "
                          "scales it); x.pfm and x.exr the mean radiance of the samples, "
                          "linear 32-bit floats, neither scaled nor clipped.");
  return ch03::run_program_main(app, argc, argv, options, [&] {
    options.up_given = app.count("--up") > 0;
    refuse_ignored_flags(app, options);
    return run(options);
  });
}
