// Chapter 06: Lambertian shading. Renders the built-in scene (or any OBJ file with --scene)
// flat and smooth, with shadows and without, on the GPU and the CPU, each by a kernel
// specialised on the features the frame uses and by the all-features kernel, against a float64
// reference; then looks for shadow acne on a convex sphere at scales 1 to 1e6. With --window
// it opens the viewer.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "camera_cli.h"
#include "obj_loader.h"
#include "program.h"
#include "rt/program_output.h"
#include "shaded_render.h"
#include "shading_report.h"

namespace {

using namespace rt;
using namespace rt::ch06;

struct ChapterOptions : ch03::ProgramOptions {
  std::string scene_path; // empty: the built-in scene
  double scale = 1.0;     // the built-in scene's size
  int subdivisions = 2;
  bool subdivisions_given = false;
  bool smooth = true;  // the image's shading
  bool shadows = true; // the image's shadows
  LightSettings lights;
  bool terminator_lift = true; // off: shadow rays leave from the flat triangle itself
  bool skip_cpu = false;
};

// The scene and the camera to start from: flags the reader gave win over the scene's own.
ShadedScene load_scene(const ChapterOptions& options, CameraSpec& camera) {
  ShadedScene scene;
  CameraSpec framed;
  if (options.scene_path.empty()) {
    scene = make_default_scene(options.subdivisions, options.scale, options.lights);
    framed = default_camera(options.scale);
  } else {
    scene = scene_from_obj(ch05::load_obj(options.scene_path), options.lights);
    framed = frame_bounds_down_z(bounds_of(scene.mesh), options.camera.fov_degrees,
                                 options.common.extent());
  }
  scene.lift_shadow_origins = options.terminator_lift;
  if (!options.eye_given) camera.eye = framed.eye;
  if (!options.target_given) camera.target = framed.target;
  return scene;
}

int run(ChapterOptions& options) {
  if (!options.scene_path.empty() && options.scale != 1.0)
    throw UsageError("--scale works on the built-in scene only");
  if (!options.scene_path.empty() && options.subdivisions_given)
    throw UsageError("--subdivisions works on the built-in scene only");
  validate_lights(options.lights);
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  CameraSpec camera = options.camera;
  const ShadedScene scene = load_scene(options, camera);
  ch03::validate_camera(camera);

  Report report = start_report("Chapter 06: Lambertian shading", "Mrays/s",
                               "float64 reference (CPU)", backend);
  report.add_context("image", to_string(options.common.extent()));
  report.add_context("scene",
                     (options.scene_path.empty() ? "built-in, " : options.scene_path + ", ") +
                         scene.description);
  report.add_context("lights", std::to_string(scene.lights.directional_count) +
                                   " directional, " + std::to_string(scene.lights.point_count) +
                                   " point, ambient " +
                                   format_fixed(options.lights.ambient, 2));
  report.add_context("error column",
                     "pixels differing from the reference, RMSE of the 8-bit R, G, B values, "
                     "NaN pixels; registers per thread (GPU); scene bytes the kernel reads "
                     "(what the GPU backend uploads)");
  report.add_context("rays", "primary + shadow rays, brute force (every ray tests every "
                             "triangle); CPU rows time one frame unless --frames says more");

  const Variant image_variant{options.smooth, options.shadows};
  const unsigned features = features_used(scene, options.smooth, options.shadows);
  std::optional<DeviceShadedScene> d_scene; // uploaded for the first GPU frame
  const ch03::ProgramParts parts{
      .chapter = "ch06",
      .window_title = "Lambertian shading",
      .camera = camera,
      .render_with_radiance =
          [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels,
              Vec3f* radiance) {
            if (b == Backend::gpu && !d_scene) d_scene.emplace(scene, features);
            const SceneView view = d_scene ? d_scene->view() : host_view(scene, features);
            render_shaded(b, KernelKind::specialised, features, view,
                          ch03::make_camera<float>(spec, extent), extent, pixels, nullptr,
                          radiance);
          },
      .window_row =
          [&](const ch03::WindowResult& shown) {
            const ShadedReference reference =
                render_shaded_reference(scene, features, shown.camera, shown.extent());
            return ch03::window_row(
                variant_name(image_variant), backend, shown,
                count_differing_pixels(shown.last_screen.pixels, reference.image.pixels));
          },
      .measure =
          [&](Report& rows) {
            const std::vector<Backend> backends = report_backends(backend, options.skip_cpu);
            report_variants(backends, scene, camera, options.common.extent(),
                            options.common.frames, rows);
            report_acne(backends, options.common.extent(), options.lights, rows);
          },
      .image_note = variant_name(image_variant),
  };
  return ch03::run_window_or_headless(options, backend, parts, report);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 06: Lambertian shading, flat and smooth, lights and shadows",
               "ch06_lambertian_shading"};
  ChapterOptions options;
  options.common.width = 640;
  options.common.height = 360;
  options.common.output = "ch06_lambertian_shading.png";
  options.camera = default_camera(1.0);
  ch03::add_program_options(app, options);
  app.add_option("--scene", options.scene_path,
                 "OBJ file to render (.obj or gzip'd); default: the built-in scene")
      ->check(CLI::ExistingFile);
  app.add_option("--scale", options.scale, "Scale the built-in scene and its camera by this")
      ->check(finite_range(1e-6, 1e7))
      ->capture_default_str();
  app.add_option("--subdivisions", options.subdivisions,
                 "Built-in icosphere's subdivisions (20 * 4^n triangles)")
      ->check(CLI::Range(0, 6))
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--shading", [&](const std::string& text) { options.smooth = text == "smooth"; },
         "Normals for the image: flat (the face's) or smooth (interpolated vertex normals)")
      ->check(CLI::IsMember({"flat", "smooth"}))
      ->default_str("smooth");
  add_on_off_option(app, "--shadows", options.shadows, "Shadow rays for the image");
  add_on_off_option(app, "--point-light", options.lights.point_light,
                    "A point light above and in front of the scene");
  app.add_option_function<std::vector<double>>(
         "--light-dir",
         [&](const std::vector<double>& v) {
           options.lights.direction = {v[0], v[1], v[2]};
         },
         "Direction towards the directional light")
      ->delimiter(',')
      ->expected(3)
      ->type_name("X,Y,Z")
      ->default_str("-0.5,1,0.7");
  app.add_option("--ambient", options.lights.ambient, "Ambient irradiance (grey), 0 to 1")
      ->capture_default_str();
  add_on_off_option(app, "--terminator-lift", options.terminator_lift,
                    "Start smooth shading's shadow rays from the lifted point (off: from the "
                    "flat triangle, to see the shadow terminator it removes)");
  app.add_flag("--skip-cpu", options.skip_cpu,
               "On the GPU, leave out the CPU rows (brute force on a large model is slow)");
  ch03::add_image_only_option(app, options);
  return ch03::run_program_main(app, argc, argv, options, [&] {
    options.subdivisions_given = app.get_option("--subdivisions")->count() > 0;
    return run(options);
  });
}
