// Chapter 05: a Wavefront OBJ model on screen. Loads --scene (plain or gzip'd; by default the
// course's own 100 000-triangle torus knot), frames it with an automatic camera and renders it
// brute force with the watertight test and with Moller-Trumbore, GPU and CPU, against a
// float64 reference; then times icospheres of growing size with the same camera, to show the
// cost of brute force growing with the triangle count. With --window it opens the viewer.
#include <chrono>
#include <iostream>
#include <optional>
#include <string>
#include <utility>

#include "camera_cli.h"
#include "index_mistakes.h"
#include "model_render.h"
#include "model_report.h"
#include "obj_loader.h"
#include "program.h"
#include "rt/program_output.h"
#include "variant_cli.h"

namespace {

using namespace rt;
using namespace rt::ch05;
using ch04::DeviceTriangleScene;

constexpr Extent k_gpu_image{1280, 720}; // default image on the GPU
constexpr Extent k_cpu_image{128, 72};   // ... and on the CPU, where brute force is slow

struct ChapterOptions : ch03::ProgramOptions { // eye and target framed unless given
  std::string scene = RT_ASSETS_DIR "/torus_knot_100k.obj.gz";
  long long reference_pixels = 128 * 72; // traced by the float64 reference and the CPU rows
  int scaling_max = 5;                   // icospheres of 20 * 4^k triangles, k = 0..this
  TriangleVariant image_variant = TriangleVariant::watertight;
  IndexMistake index_mistake = IndexMistake::none; // the original loader's bugs, to see them
};

// The automatic camera frames the model's bounding box; --eye and --target, where given,
// replace its choice.
CameraSpec choose_camera(const ChapterOptions& options, const ObjMesh& mesh, Extent extent) {
  CameraSpec camera = options.camera;
  if (!options.eye_given || !options.target_given) {
    // The framing reads the field of view and looks along k_framing_direction: check those
    // flags (and up) first, so that a bad one is named as such.
    CameraSpec flags = options.camera;
    flags.target = {};
    flags.eye = k_framing_direction;
    ch03::validate_camera(flags);
    camera = frame_bounds(mesh.bounds_min, mesh.bounds_max, options.camera, extent);
    if (options.eye_given) camera.eye = options.camera.eye;
    if (options.target_given) camera.target = options.camera.target;
  }
  ch03::validate_camera(camera);
  return camera;
}

int run(ChapterOptions options) {
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  const Extent image = backend == Backend::gpu ? k_gpu_image : k_cpu_image;
  if (!options.width_given) options.common.width = image.width;
  if (!options.height_given) options.common.height = image.height;

  const auto load_start = std::chrono::steady_clock::now();
  ObjMesh mesh = load_obj(options.scene);
  const double load_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_start)
          .count();
  const CameraSpec camera = choose_camera(options, mesh, options.common.extent());
  // Brute force over a large model traces thousands of rays per second, not millions.
  Report report = start_report("Chapter 05: a Wavefront OBJ model, brute force", "krays/s",
                               "float64 reference (CPU)", backend);
  add_model_context(report, options.scene, mesh, load_ms, camera,
                    options.eye_given || options.target_given);
  if (options.index_mistake != IndexMistake::none)
    report.add_context("index mistake", "the triangles are built wrongly on purpose");
  const Vec3d lo = mesh.bounds_min.as<double>(), hi = mesh.bounds_max.as<double>();
  TriangleScene mistaken = take_scene(mesh); // mesh keeps its bounds and counts only
  repeat_index_mistake(mistaken, options.index_mistake);
  const TriangleScene scene = std::move(mistaken);

  const ModelMeasurements measurements{
      .extent = options.common.extent(),
      .size_from_backend = !options.width_given && !options.height_given,
      .reference_pixels = options.reference_pixels,
      .scaling_max = options.scaling_max,
      .centre = (lo + hi) * 0.5,
      .radius = 0.5 * length(hi - lo),
      .image_variant = options.image_variant,
      .frames = options.common.frames,
      .scene_path = options.scene,
  };
  std::optional<Image> picture;               // a measured frame that --output can show
  std::optional<DeviceTriangleScene> d_scene; // uploaded for the window's first GPU frame
  const ch03::ProgramParts parts{
      .chapter = "ch05",
      .window_title = options.scene,
      .camera = camera,
      .render =
          [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
            const auto frame_camera = ch03::make_camera<float>(spec, extent);
            const PixelSample whole{extent, 1};
            if (b == Backend::cpu) {
              render_model(b, options.image_variant, ch04::host_view(scene.mesh),
                           scene.object.data(), frame_camera, whole, pixels);
              return;
            }
            if (!d_scene) {
              check_device_memory(device_bytes_needed(scene, extent), options.scene);
              d_scene.emplace(scene);
            }
            render_model(b, options.image_variant, d_scene->view(), d_scene->object(),
                         frame_camera, whole, pixels);
          },
      .window_row =
          [&](const ch03::WindowResult& shown) {
            return sampled_window_row(shown, backend, scene, options.image_variant,
                                      options.reference_pixels);
          },
      .window_context = {{"error", "over a sample of the last frame's pixels, at most " +
                                       group_digits(options.reference_pixels)}},
      .measure =
          [&](Report& rows) {
            picture = report_model(backend, scene, camera, measurements, rows);
          },
      // When the CPU traced a sample only, the whole image is rendered once more, untimed.
      .image =
          [&] {
            return picture ? std::move(*picture)
                           : render_image_on_cpu(scene, camera, measurements.extent,
                                                 options.image_variant);
          },
      .image_note = ch04::to_string(options.image_variant),
  };
  return ch03::run_window_or_headless(options, backend, parts, report);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 05: a Wavefront OBJ model, brute force", "ch05_obj_loading"};
  ChapterOptions options;
  options.common.output = "ch05_obj_loading.png";
  ch03::add_program_options(app, options);
  app.get_option("--width")->default_str("1280 on the GPU, 128 on the CPU");
  app.get_option("--height")->default_str("720 on the GPU, 72 on the CPU");
  app.get_option("--eye")->default_str("framed from the model's bounds");
  app.get_option("--target")->default_str("the centre of the model's bounds");
  app.add_option("--scene", options.scene, "OBJ file to load (plain or gzip-compressed)")
      ->capture_default_str();
  app.add_option("--reference-pixels", options.reference_pixels,
                 "Most pixels the float64 reference and the CPU rows trace (a regular sample "
                 "of the image)")
      ->check(CLI::Range(1LL, static_cast<long long>(k_max_image_side) * k_max_image_side))
      ->capture_default_str();
  app.add_option("--scaling-max", options.scaling_max,
                 "Largest icosphere of the brute-force rows: 20 * 4^N triangles; -1: none")
      ->check(CLI::Range(-1, 7))
      ->capture_default_str();
  ch04::add_triangle_variant_option(app, options.image_variant);
  app.add_option_function<std::string>(
         "--index-mistake",
         [&](const std::string& text) { options.index_mistake = parse_index_mistake(text); },
         "Build the triangles as the original loader's bugs would, to see the picture: "
         "minus-one (OBJ's 1 subtracted twice) or file-order (vertices 3i, 3i+1, 3i+2)")
      ->check(CLI::IsMember({"none", "minus-one", "file-order"}))
      ->default_str("none");
  app.footer("Brute force on the CPU takes seconds per frame for large models: try the window "
             "there with --scene " RT_ASSETS_DIR "/cornell_room.obj.gz.");
  return ch03::run_program_main(app, argc, argv, options, [&] { return run(options); });
}
