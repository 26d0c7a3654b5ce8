// Chapter 05: a Wavefront OBJ model on screen. Loads --scene (plain or gzip'd; by default the
// course's own 100 000-triangle torus knot), frames it with an automatic camera and renders it
// brute force with the watertight test and with Moller-Trumbore, GPU and CPU, against a
// float64 reference; then times icospheres of growing size with the same camera, to show the
// cost of brute force growing with the triangle count. With --window it opens the viewer.
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "camera_cli.h"
#include "mesh_render.h"
#include "model_render.h"
#include "obj_loader.h"
#include "progress.h"
#include "rt/backend_image.h"
#include "rt/cli.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "variant_cli.h"
#include "viewer.h"
#include "window_loop.h"

namespace {

using namespace rt;
using namespace rt::ch05;
using ch04::DeviceTriangleScene;
using ch04::MeshFrameError;
using ch04::MeshPixelRecord;
using ch04::MeshReference;

constexpr Extent k_gpu_image{1280, 720}; // default image on the GPU
constexpr Extent k_cpu_image{128, 72};   // ... and on the CPU, where brute force is slow
constexpr TriangleVariant k_variants[] = {TriangleVariant::watertight,
                                          TriangleVariant::moller_trumbore};

struct ChapterOptions {
  CommonOptions common;
  CameraSpec camera; // eye and target are framed automatically unless given
  bool eye_given = false, target_given = false;
  bool width_given = false, height_given = false;
  std::string scene = RT_ASSETS_DIR "/torus_knot_100k.obj.gz";
  long long reference_pixels = 128 * 72; // traced by the float64 reference and the CPU rows
  int scaling_max = 5;                   // icospheres of 20 * 4^k triangles, k = 0..this
  TriangleVariant image_variant = TriangleVariant::watertight;
  ch03::DisplayChoice display;
};

std::string vec_text(Vec3d v) {
  std::ostringstream text;
  text.precision(4);
  text << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return text.str();
}

std::string size_text(Extent e) {
  return std::to_string(e.width) + "x" + std::to_string(e.height);
}

// "1 triangle", "100 000 triangles".
std::string count_text(std::size_t n, const char* singular, const char* plural) {
  return group_digits(static_cast<long long>(n)) + " " + (n == 1 ? singular : plural);
}

std::string describe_model(const ObjMesh& mesh) {
  const auto objects = static_cast<std::size_t>(mesh.object_count);
  const auto degenerate = static_cast<std::size_t>(mesh.degenerate_triangle_count);
  return count_text(mesh.geometry.triangles.size(), "triangle", "triangles") + ", " +
         count_text(mesh.geometry.vertices.size(), "vertex", "vertices") + ", normals: " +
         (mesh.normals.empty() ? "no" : "yes (" + group_digits(mesh.normals.size()) + ")") +
         ", texture coordinates: " + (mesh.texcoords.empty() ? "no" : "yes") + ", " +
         count_text(objects, "object", "objects") + ", " +
         count_text(mesh.material_names.size(), "material", "materials") + ", " +
         group_digits(static_cast<long long>(degenerate)) + " degenerate";
}

// A frame of the sample's pixels, timed: on the GPU the protocol's plan (CUDA events), on the
// CPU one run unless --frames asks for more, with a progress line while it takes long.
struct TimedFrame {
  Image image;
  std::vector<MeshPixelRecord> records;
  Timing timing;
};

TimedFrame render_timed(Backend backend, TriangleVariant variant, const TriangleScene& scene,
                        const DeviceTriangleScene* d_scene, const ch03::Camera<float>& camera,
                        PixelSample sample, int frames, const std::string& what) {
  const Extent extent = sample.extent();
  TimedFrame frame{Image(extent.width, extent.height),
                   std::vector<MeshPixelRecord>(extent.pixel_count()),
                   {}};
  if (backend == Backend::gpu) {
    DeviceBuffer<Rgba8> d_pixels(frame.image.pixels.size());
    DeviceBuffer<MeshPixelRecord> d_records(frame.records.size());
    frame.timing = time_on(
        backend,
        [&] {
          render_model(backend, variant, d_scene->view(), d_scene->object(), camera, sample,
                       d_pixels.data(), d_records.data());
        },
        frames);
    d_pixels.download(frame.image.pixels);
    d_records.download(frame.records);
  } else {
    const int runs = frames > 0 ? frames : 1;
    Progress progress(what, extent.height * runs, std::cerr);
    frame.timing = time_cpu(
        [&] {
          render_model(backend, variant, ch04::host_view(scene.mesh), scene.object.data(),
                       camera, sample, frame.image.pixels.data(), frame.records.data(),
                       progress.rows_done());
        },
        {0, runs});
  }
  return frame;
}

// The frame's error over the reference's sample of its pixels.
MeshFrameError error_of(const TimedFrame& frame, PixelSample frame_sample,
                        PixelSample reference_sample, const MeshReference& reference) {
  if (frame_sample.stride == reference_sample.stride)
    return ch04::compare_with_reference(frame.image, frame.records, reference);
  const Extent e = reference_sample.extent();
  Image image(e.width, e.height);
  image.pixels = sampled(frame.image.pixels, reference_sample);
  return ch04::compare_with_reference(image, sampled(frame.records, reference_sample),
                                      reference);
}

ReportRow render_row(const std::string& name, Backend backend, const TimedFrame& frame,
                     const MeshFrameError& e) {
  const long long rays = static_cast<long long>(frame.image.pixels.size());
  return {name,
          to_string(backend),
          frame.timing.median_ms,
          rays / frame.timing.median_ms, // rays per ms: krays/s
          group_digits(e.pixels_differing) + " px differ, " + group_digits(e.holes) +
              " holes, " + group_digits(e.nan_pixels) + " NaN",
          {{"pixels_differing", double(e.pixels_differing)},
           {"holes", double(e.holes)},
           {"nan_pixels", double(e.nan_pixels)},
           {"rays", double(rays)}}};
}

// A brute-force row of the scaling table: time against triangle count.
ReportRow scaling_row(const std::string& name, Backend backend, const Timing& timing,
                      long long rays, long long triangles, const std::string& note) {
  const double ns_per_test = timing.median_ms * 1e6 / (double(rays) * double(triangles));
  std::ostringstream error;
  error.precision(3);
  error << note << ns_per_test << " ns per ray-triangle test";
  return {name,
          to_string(backend),
          timing.median_ms,
          rays / timing.median_ms,
          error.str(),
          {{"triangles", double(triangles)}, {"ns_per_test", ns_per_test}}};
}

// Icospheres of 20 * 4^k triangles where the model is, through the same camera: brute force
// tests every triangle for every ray, so the time per frame grows with the triangle count.
void add_scaling_rows(const ChapterOptions& options, Backend backend, Vec3d centre,
                      double radius, const ch03::Camera<float>& camera, PixelSample sample,
                      Report& report) {
  for (int k = 0; k <= options.scaling_max; ++k) {
    TriangleScene sphere{ch04::make_icosphere(k, centre, radius), {}};
    sphere.object.assign(sphere.mesh.triangles.size(), -1);
    const auto triangles = static_cast<long long>(sphere.mesh.triangles.size());
    const std::string name = "brute force, icosphere, " +
                             count_text(sphere.mesh.triangles.size(), "triangle", "triangles");
    std::optional<DeviceTriangleScene> d_sphere;
    if (backend == Backend::gpu) d_sphere.emplace(sphere);
    const TimedFrame frame = render_timed(backend, TriangleVariant::watertight, sphere,
                                          d_sphere ? &*d_sphere : nullptr, camera, sample,
                                          options.common.frames, name);
    report.add_row(
        scaling_row(name, backend, frame.timing, sample.extent().pixel_count(), triangles, ""));
  }
}

void run_headless(const ChapterOptions& options, Backend backend, const TriangleScene& scene,
                  Vec3d centre, double radius, const CameraSpec& spec, Report& report) {
  const Extent extent = options.common.extent();
  const PixelSample whole{extent, 1};
  const PixelSample sample = sample_of(extent, options.reference_pixels);
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  const int frames = options.common.frames;
  std::optional<DeviceTriangleScene> d_scene;
  if (backend == Backend::gpu) {
    check_device_memory(device_bytes_needed(scene, extent), options.scene);
    d_scene.emplace(scene);
  }

  MeshReference reference;
  Timing reference_time;
  {
    Progress progress("float64 reference", sample.extent().height, std::cerr);
    reference_time = time_cpu(
        [&] { reference = render_model_reference(scene, spec, sample, progress.rows_done()); },
        {0, 1});
  }

  std::optional<Image> picture; // what --output writes
  std::optional<Timing> model_time;
  if (backend == Backend::gpu) {
    for (TriangleVariant variant : k_variants) {
      const std::string name =
          std::string("render ") + size_text(extent) + ", " + ch04::to_string(variant);
      TimedFrame frame =
          render_timed(backend, variant, scene, &*d_scene, camera, whole, frames, name);
      report.add_row(
          render_row(name, backend, frame, error_of(frame, whole, sample, reference)));
      if (variant == TriangleVariant::watertight) model_time = frame.timing;
      if (variant == options.image_variant) picture = std::move(frame.image);
    }
  }
  for (TriangleVariant variant : k_variants) {
    const std::string name = std::string("render ") + size_text(sample.extent()) +
                             (sample.stride > 1 ? " sample, " : ", ") +
                             ch04::to_string(variant);
    TimedFrame frame =
        render_timed(Backend::cpu, variant, scene, nullptr, camera, sample, frames, name);
    report.add_row(
        render_row(name, Backend::cpu, frame,
                   ch04::compare_with_reference(frame.image, frame.records, reference)));
    if (backend == Backend::cpu && variant == TriangleVariant::watertight)
      model_time = frame.timing;
    if (backend == Backend::cpu && sample.stride == 1 && variant == options.image_variant)
      picture = std::move(frame.image);
  }
  report.add_row({"render " + size_text(sample.extent()) + ", float64 reference (watertight)",
                  "cpu",
                  reference_time.median_ms,
                  sample.extent().pixel_count() / reference_time.median_ms,
                  "reference",
                  {}});

  if (options.scaling_max >= 0) {
    const auto triangles = static_cast<long long>(scene.mesh.triangles.size());
    const PixelSample scaling_sample = backend == Backend::gpu ? whole : sample;
    add_scaling_rows(options, backend, centre, 0.6 * radius, camera, scaling_sample, report);
    report.add_row(
        scaling_row("brute force, the model, " +
                        count_text(scene.mesh.triangles.size(), "triangle", "triangles"),
                    backend, *model_time, scaling_sample.extent().pixel_count(), triangles,
                    "the watertight row above: "));
  }

  if (options.common.output.empty()) return;
  if (!picture) { // the CPU traced a sample only: the whole image once more, untimed
    const auto start = std::chrono::steady_clock::now();
    Progress progress("image " + size_text(extent), extent.height, std::cerr);
    picture = render_into_image(Backend::cpu, extent, [&](Rgba8* pixels) {
      render_model(Backend::cpu, options.image_variant, ch04::host_view(scene.mesh),
                   scene.object.data(), camera, whole, pixels, nullptr, progress.rows_done());
    });
    const auto seconds = static_cast<long long>(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() + 0.5);
    std::cout << "rendered the " << size_text(extent) << " image on the CPU in " << seconds
              << " s\n";
  }
  write_image(options.common.output, *picture);
  std::cout << "wrote " << options.common.output << " ("
            << ch04::to_string(options.image_variant) << ")\n";
}

void run_window(const ChapterOptions& options, Backend backend, ch02::Viewer& viewer,
                const TriangleScene& scene, const CameraSpec& start, Report& report) {
  std::optional<DeviceTriangleScene> d_scene;
  if (backend == Backend::gpu) {
    check_device_memory(device_bytes_needed(scene, viewer.size()), options.scene);
    d_scene.emplace(scene);
  }
  const ch03::WindowSettings window{"ch05: " + options.scene, options.common.frames,
                                    "ch05_screenshot"};
  const ch03::WindowResult shown =
      ch03::run_window(viewer, backend, start, window,
                       [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
                         const auto camera = ch03::make_camera<float>(spec, extent);
                         const PixelSample whole{extent, 1};
                         if (b == Backend::gpu)
                           render_model(b, options.image_variant, d_scene->view(),
                                        d_scene->object(), camera, whole, pixels);
                         else
                           render_model(b, options.image_variant, ch04::host_view(scene.mesh),
                                        scene.object.data(), camera, whole, pixels);
                       });
  if (shown.frames == 0) return;
  const Extent extent{shown.last_screen.width, shown.last_screen.height};
  const PixelSample sample = sample_of(extent, options.reference_pixels);
  const MeshReference reference = render_model_reference(scene, shown.camera, sample);
  const auto differing =
      count_differing_pixels(sampled(shown.last_screen.pixels, sample), reference.image.pixels);
  report.add_row({std::string("render ") + size_text(extent) + ", " +
                      ch04::to_string(options.image_variant) + ", window (" + shown.path + ")",
                  to_string(backend),
                  shown.frame_time.median_ms,
                  extent.pixel_count() / shown.frame_time.median_ms,
                  group_digits(static_cast<long long>(differing)) + " of " +
                      group_digits(sample.extent().pixel_count()) +
                      " sampled px differ on screen",
                  {{"pixels_differing", double(differing)}}});
  if (options.common.frames > 0 && !options.common.output.empty()) {
    write_image(options.common.output, shown.last_screen);
    std::cout << "wrote " << options.common.output << " (screenshot)\n";
  }
}

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
  const Vec3d lo = mesh.bounds_min.as<double>(), hi = mesh.bounds_max.as<double>();

  // Brute force over a large model traces thousands of rays per second, not millions.
  Report report("Chapter 05: a Wavefront OBJ model, brute force", "krays/s",
                "float64 reference (CPU)");
  report.add_context("device", describe_backend(backend));
  report.add_context("scene", options.scene);
  report.add_context("model", describe_model(mesh));
  report.add_context("bounds", vec_text(lo) + " to " + vec_text(hi));
  std::ostringstream load_text;
  load_text.precision(3);
  load_text << load_ms << " ms (read, gunzip, line checks, tinyobjloader, triangles)";
  report.add_context("load", load_text.str());
  report.add_context("camera", std::string(options.eye_given || options.target_given
                                               ? "from the flags"
                                               : "framed automatically") +
                                   ": eye " + vec_text(camera.eye) + ", target " +
                                   vec_text(camera.target));
  const TriangleScene scene = take_scene(mesh); // mesh keeps its bounds and counts only

  const std::unique_ptr<ch02::Viewer> viewer =
      ch03::open_viewer(options.display, options.common.extent(), "ch05: OBJ model");
  if (viewer) {
    report.add_context("mode", ch03::k_window_mode);
    report.add_context("error", "over a sample of the last frame's pixels, at most " +
                                    group_digits(options.reference_pixels));
    run_window(options, backend, *viewer, scene, camera, report);
  } else {
    const PixelSample sample = sample_of(options.common.extent(), options.reference_pixels);
    report.add_context("mode", ch03::k_headless_mode);
    report.add_context(
        "image", size_text(options.common.extent()) +
                     (backend == Backend::cpu && !options.width_given && !options.height_given
                          ? " (the CPU's default: --width and --height set it)"
                          : ""));
    if (sample.stride > 1)
      report.add_context("sample", "CPU rows and the reference trace the middle pixel of "
                                   "each " +
                                       std::to_string(sample.stride) + "x" +
                                       std::to_string(sample.stride) + " block (" +
                                       size_text(sample.extent()) +
                                       "); GPU rows are compared there");
    const Extent brute_force =
        backend == Backend::gpu ? options.common.extent() : sample.extent();
    report.add_context("brute force rows", "the same camera, every ray against every "
                                           "triangle, on the " +
                                               std::string(to_string(backend)) + " at " +
                                               size_text(brute_force));
    run_headless(options, backend, scene, (lo + hi) * 0.5, 0.5 * length(hi - lo), camera,
                 report);
  }
  report.print(std::cout);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 05: a Wavefront OBJ model, brute force", "ch05_obj_loading"};
  ChapterOptions options;
  options.common.output = "ch05_obj_loading.png";
  add_common_options(app, options.common);
  app.get_option("--width")->default_str("1280 on the GPU, 128 on the CPU");
  app.get_option("--height")->default_str("720 on the GPU, 72 on the CPU");
  ch03::add_camera_options(app, options.camera);
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
  ch03::add_display_options(app, options.display);
  app.footer(app.get_footer() + " Brute force on the CPU takes seconds per frame for large "
                                "models: try the window there with --scene " RT_ASSETS_DIR
                                "/cornell_room.obj.gz.");
  return run_main(app, argc, argv, [&] {
    options.eye_given = app.get_option("--eye")->count() > 0;
    options.target_given = app.get_option("--target")->count() > 0;
    options.width_given = app.get_option("--width")->count() > 0;
    options.height_given = app.get_option("--height")->count() > 0;
    if (!options.common.output.empty()) check_image_path(options.common.output);
    return run(options);
  });
}
