// Chapter 06: Lambertian shading. Renders the built-in scene (or any OBJ file with --scene)
// flat and smooth, with shadows and without, on the GPU and the CPU, each by a kernel
// specialised on the features the frame uses and by the all-features kernel, against a float64
// reference; then looks for shadow acne on a convex sphere at scales 1 to 1e6. With --window
// it opens the viewer.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera_cli.h"
#include "obj_loader.h"
#include "rt/backend_image.h"
#include "rt/cli.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "shaded_render.h"
#include "viewer.h"
#include "window_loop.h"

namespace {

using namespace rt;
using namespace rt::ch06;

struct ChapterOptions {
  CommonOptions common;
  CameraSpec camera = default_camera(1.0);
  bool eye_given = false, target_given = false; // else the scene decides
  std::string scene_path;                       // empty: the built-in scene
  double scale = 1.0;                           // the built-in scene's size
  int subdivisions = 2;
  bool smooth = true;  // the image's shading
  bool shadows = true; // the image's shadows
  LightSettings lights;
  bool skip_cpu = false;
  bool image_only = false; // headless: write --output, measure nothing
  ch03::DisplayChoice display;
};

struct Variant {
  bool smooth;
  bool shadows;
};
constexpr Variant k_variants[] = {{false, false}, {false, true}, {true, false}, {true, true}};

std::string variant_name(Variant v) {
  return std::string(v.smooth ? "smooth" : "flat") + (v.shadows ? ", shadows" : ", no shadows");
}

// A frame rendered and timed on one backend by one kind of kernel.
struct MeasuredFrame {
  Image image;
  std::vector<ShadedPixelRecord> records;
  Timing timing;
  std::size_t bytes = 0; // scene bytes the kernel reads (uploaded, on the GPU)
  int registers = -1;    // per thread, GPU only
};

MeasuredFrame measure_frame(Backend backend, KernelKind kind, unsigned features,
                            const ShadedScene& scene, const ch03::Camera<float>& camera,
                            Extent extent, int frames) {
  MeasuredFrame out{Image(extent.width, extent.height),
                    std::vector<ShadedPixelRecord>(extent.pixel_count()),
                    {},
                    scene_bytes(scene, uploaded_features(kind, features)),
                    -1};
  if (backend == Backend::gpu) {
    const DeviceShadedScene d_scene(scene, uploaded_features(kind, features));
    DeviceBuffer<Rgba8> d_pixels(out.image.pixels.size());
    DeviceBuffer<ShadedPixelRecord> d_records(out.records.size());
    out.timing = time_on(
        backend,
        [&] {
          render_shaded(backend, kind, features, d_scene.view(), camera, extent,
                        d_pixels.data(), d_records.data());
        },
        frames);
    d_pixels.download(out.image.pixels);
    d_records.download(out.records);
    out.bytes = d_scene.bytes_uploaded();
    out.registers = kernel_registers(kind, features);
  } else {
    // Brute force on CPU cores takes a second or more a frame: one timed frame unless asked.
    const SceneView view = host_view(scene, uploaded_features(kind, features));
    out.timing = time_cpu(
        [&] {
          render_shaded(backend, kind, features, view, camera, extent, out.image.pixels.data(),
                        out.records.data());
        },
        {0, frames > 0 ? frames : 1});
  }
  return out;
}

ReportRow frame_row(const std::string& name, Backend backend, const MeasuredFrame& frame,
                    Extent extent, const ShadedFrameError& e, const std::string& extra) {
  const double rays = double(extent.pixel_count()) + double(e.shadow_rays);
  const std::string registers =
      frame.registers >= 0 ? std::to_string(frame.registers) + " regs" : "n/a regs";
  ReportRow row{name,
                to_string(backend),
                frame.timing.median_ms,
                rays / (frame.timing.median_ms * 1e3),
                group_digits(e.pixels_differing) + " px differ, RMSE " +
                    format_fixed(e.rmse, 3) + ", " + group_digits(e.nan_pixels) + " NaN; " +
                    registers + ", " + group_digits(static_cast<long long>(frame.bytes)) +
                    " B" + extra,
                {{"pixels_differing", double(e.pixels_differing)},
                 {"rmse_8bit", e.rmse},
                 {"nan_pixels", double(e.nan_pixels)},
                 {"shadow_rays", double(e.shadow_rays)},
                 {"scene_bytes", double(frame.bytes)}}};
  if (frame.registers >= 0) row.metrics.emplace_back("registers", frame.registers);
  return row;
}

// Flat and smooth, shadows off and on: each by the specialised and the all-features kernel on
// each backend, against the float64 reference.
void report_variants(const ChapterOptions& options, const std::vector<Backend>& backends,
                     const ShadedScene& scene, const CameraSpec& spec, Report& report) {
  const Extent extent = options.common.extent();
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  for (const Variant variant : k_variants) {
    const unsigned features = features_used(scene, variant.smooth, variant.shadows);
    ShadedReference reference;
    const Timing reference_time = time_cpu(
        [&] { reference = render_shaded_reference(scene, features, spec, extent); }, {0, 1});
    for (const Backend backend : backends) {
      std::optional<MeasuredFrame> specialised;
      for (const KernelKind kind : {KernelKind::specialised, KernelKind::all_features}) {
        MeasuredFrame frame = measure_frame(backend, kind, features, scene, camera, extent,
                                            options.common.frames);
        const ShadedFrameError e =
            compare_with_reference(frame.image, frame.records, reference.image);
        std::string extra;
        if (specialised) {
          const auto differing =
              count_differing_pixels(frame.image.pixels, specialised->image.pixels);
          extra = differing == 0 ? "; image identical"
                                 : "; " + group_digits(static_cast<long long>(differing)) +
                                       " px differ from specialised";
        }
        report.add_row(frame_row(variant_name(variant) + ", " + to_string(kind), backend, frame,
                                 extent, e, extra));
        if (!specialised) specialised = std::move(frame);
      }
    }
    report.add_row({variant_name(variant) + ", float64 reference",
                    "cpu",
                    reference_time.median_ms,
                    double(reference.rays) / (reference_time.median_ms * 1e3),
                    "reference",
                    {}});
  }
}

// A convex sphere at scales 1 to 1e6, flat, with shadows: any shadow ray blocked on a face
// that faces its light is acne.
void report_acne(const ChapterOptions& options, const std::vector<Backend>& backends,
                 Report& report) {
  const Extent extent{std::min(options.common.width, 320),
                      std::min(options.common.height, 180)};
  for (const double scale : {1.0, 1e3, 1e6}) {
    const ShadedScene sphere = make_lone_sphere(2, scale, options.lights);
    const CameraSpec spec = frame_bounds(bounds_of(sphere.mesh), 40.0);
    const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
    const unsigned features = features_used(sphere, false, true);
    for (const Backend backend : backends) {
      const MeasuredFrame frame =
          measure_frame(backend, KernelKind::specialised, features, sphere, camera, extent, 1);
      long long rays = 0, acne = 0;
      for (const ShadedPixelRecord& r : frame.records) {
        rays += r.shadow_rays;
        acne += r.shadowed_facing;
      }
      char name[64];
      std::snprintf(name, sizeof name, "shadow acne, convex sphere at scale %.0e", scale);
      report.add_row({name,
                      to_string(backend),
                      frame.timing.median_ms,
                      double(extent.pixel_count() + rays) / (frame.timing.median_ms * 1e3),
                      group_digits(acne) + " of " + group_digits(rays) +
                          " shadow rays blocked on faces facing their light",
                      {{"self_shadowed", double(acne)}, {"shadow_rays", double(rays)}}});
    }
  }
}

void render_image(const ChapterOptions& options, Backend backend, const ShadedScene& scene,
                  const CameraSpec& spec) {
  const Extent extent = options.common.extent();
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  const unsigned features = features_used(scene, options.smooth, options.shadows);
  const Image image = render_into_image(backend, extent, [&](Rgba8* pixels) {
    if (backend == Backend::gpu) {
      const DeviceShadedScene d_scene(scene, features);
      render_shaded(backend, KernelKind::specialised, features, d_scene.view(), camera, extent,
                    pixels);
    } else {
      render_shaded(backend, KernelKind::specialised, features, host_view(scene, features),
                    camera, extent, pixels);
    }
  });
  write_image(options.common.output, image);
  std::cout << "wrote " << options.common.output << " ("
            << variant_name({options.smooth, options.shadows}) << ")\n";
}

void run_window(const ChapterOptions& options, Backend backend, ch02::Viewer& viewer,
                const ShadedScene& scene, const CameraSpec& start, Report& report) {
  const unsigned features = features_used(scene, options.smooth, options.shadows);
  std::optional<DeviceShadedScene> d_scene;
  if (backend == Backend::gpu) d_scene.emplace(scene, features);
  const ch03::WindowSettings window{"ch06: Lambertian shading", options.common.frames,
                                    "ch06_screenshot"};
  const ch03::WindowResult shown =
      ch03::run_window(viewer, backend, start, window,
                       [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
                         const SceneView view =
                             d_scene ? d_scene->view() : host_view(scene, features);
                         render_shaded(b, KernelKind::specialised, features, view,
                                       ch03::make_camera<float>(spec, extent), extent, pixels);
                       });
  if (shown.frames == 0) return;
  const Extent extent{shown.last_screen.width, shown.last_screen.height};
  const ShadedReference reference =
      render_shaded_reference(scene, features, shown.camera, extent);
  const auto differing =
      count_differing_pixels(shown.last_screen.pixels, reference.image.pixels);
  report.add_row(
      {variant_name({options.smooth, options.shadows}) + ", window (" + shown.path + ")",
       to_string(backend),
       shown.frame_time.median_ms,
       extent.pixel_count() / (shown.frame_time.median_ms * 1e3),
       group_digits(static_cast<long long>(differing)) + " px differ on screen",
       {{"pixels_differing", double(differing)}}});
  if (options.common.frames > 0 && !options.common.output.empty()) {
    write_image(options.common.output, shown.last_screen);
    std::cout << "wrote " << options.common.output << " (screenshot)\n";
  }
}

// The scene and the camera to start from: flags the reader gave win over the scene's own.
ShadedScene load_scene(const ChapterOptions& options, CameraSpec& camera) {
  ShadedScene scene;
  CameraSpec framed;
  if (options.scene_path.empty()) {
    scene = make_default_scene(options.subdivisions, options.scale, options.lights);
    framed = default_camera(options.scale);
  } else {
    scene = scene_from_obj(ch05::load_obj(options.scene_path), options.lights);
    framed = frame_bounds(bounds_of(scene.mesh), options.camera.fov_degrees);
  }
  if (!options.eye_given) camera.eye = framed.eye;
  if (!options.target_given) camera.target = framed.target;
  return scene;
}

int run(ChapterOptions& options) {
  if (!options.scene_path.empty() && options.scale != 1.0)
    throw UsageError("--scale works on the built-in scene only");
  validate_lights(options.lights);
  ch03::validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  CameraSpec camera = options.camera;
  const ShadedScene scene = load_scene(options, camera);
  ch03::validate_camera(camera);

  Report report("Chapter 06: Lambertian shading", "Mrays/s", "float64 reference (CPU)");
  report.add_context("device", describe_backend(backend));
  report.add_context("image", std::to_string(options.common.width) + "x" +
                                  std::to_string(options.common.height));
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

  const std::unique_ptr<ch02::Viewer> viewer =
      ch03::open_viewer(options.display, options.common.extent(), "ch06: Lambertian shading");
  if (viewer) {
    report.add_context("mode", ch03::k_window_mode);
    run_window(options, backend, *viewer, scene, camera, report);
  } else {
    if (options.image_only) {
      if (options.common.output.empty()) throw UsageError("--image-only needs --output");
      render_image(options, backend, scene, camera);
      return 0;
    }
    report.add_context("mode", ch03::k_headless_mode);
    const std::vector<Backend> backends = report_backends(backend, options.skip_cpu);
    report_variants(options, backends, scene, camera, report);
    report_acne(options, backends, report);
    if (!options.common.output.empty()) render_image(options, backend, scene, camera);
  }
  report.print(std::cout);
  if (!options.common.json.empty()) report.write_json(options.common.json);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 06: Lambertian shading, flat and smooth, lights and shadows",
               "ch06_lambertian_shading"};
  ChapterOptions options;
  options.common.width = 640;
  options.common.height = 360;
  options.common.output = "ch06_lambertian_shading.png";
  add_common_options(app, options.common);
  ch03::add_camera_options(app, options.camera);
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
  app.add_flag("--skip-cpu", options.skip_cpu,
               "On the GPU, leave out the CPU rows (brute force on a large model is slow)");
  app.add_flag("--image-only", options.image_only,
               "Headless: write the --output image and skip the measurements");
  ch03::add_display_options(app, options.display);
  return run_main(app, argc, argv, [&] {
    options.eye_given = app.get_option("--eye")->count() > 0;
    options.target_given = app.get_option("--target")->count() > 0;
    if (!options.common.output.empty()) check_image_path(options.common.output);
    return run(options);
  });
}
