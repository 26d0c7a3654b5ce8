// Chapter 03: spheres seen through a real camera. Renders the default scene (a ground sphere
// of radius 1e5, mirror and coloured spheres, far moons) with the textbook and the stable
// ray/sphere intersection, on the GPU and the CPU, and reports each against the float64
// reference of the same scene. With --window it opens the interactive viewer.
#include <iostream>
#include <map>
#include <string>

#include "camera_cli.h"
#include "program.h"
#include "render.h"
#include "rt/program_output.h"
#include "sphere_report.h"

namespace {

using namespace rt;
using namespace rt::ch03;

struct ChapterOptions : ProgramOptions {
  int max_depth = 4;
  SphereVariant image_variant = SphereVariant::stable;
  double scale = 1.0;        // every length of the scene and the camera's eye and target
  float fixed_offset = 0.0f; // > 0: mirror rays start this far off the surface
};

CameraSpec scaled(CameraSpec camera, double factor) {
  camera.eye = camera.eye * factor;
  camera.target = camera.target * factor;
  return camera;
}

int run(const ChapterOptions& options) {
  validate_camera(options.camera);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  const SphereScene<float> scene = make_default_scene().scaled(float(options.scale));
  const CameraSpec camera = scaled(options.camera, options.scale);
  Report report =
      start_report("Chapter 03: spheres", "Mrays/s", "float64 reference (CPU)", backend);
  report.add_context(
      "image", to_string(options.common.extent()) + ", " +
                   (options.camera.kind == CameraKind::pinhole ? "pinhole" : "orthographic") +
                   " camera, mirror depth " + std::to_string(options.max_depth));
  report.add_context("scene", "ground sphere r=1e5, 3 spheres, 3 moons at r/D 1/300..1/3000" +
                                  (options.scale != 1.0
                                       ? ", scaled by " + format_scientific(options.scale)
                                       : std::string()));
  if (options.fixed_offset > 0.0f)
    report.add_context("mirror rays", "start " + format_scientific(options.fixed_offset) +
                                          " off the surface (a fixed offset)");

  const TraceSettings settings{options.image_variant, options.max_depth, options.fixed_offset};
  const ProgramParts parts{
      .chapter = "ch03",
      .window_title = "spheres",
      .camera = camera,
      .render =
          [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
            render_spheres(b, scene, make_camera<float>(spec, extent), extent, settings,
                           pixels);
          },
      // The last frame on screen against the float64 reference of the same camera.
      .window_row =
          [&](const WindowResult& shown) {
            const ReferenceFrame reference =
                render_reference(scene, shown.camera, shown.extent(), options.max_depth);
            return window_row(
                to_string(options.image_variant), backend, shown,
                count_differing_pixels(shown.last_screen.pixels, reference.image.pixels));
          },
      .measure =
          [&](Report& rows) {
            report_sphere_variants(backend, scene, camera, options.common.extent(), settings,
                                   options.common.frames, rows);
          },
      .image_note = to_string(options.image_variant),
  };
  return run_window_or_headless(options, backend, parts, report);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 03: spheres, a real camera, textbook vs stable intersection",
               "ch03_spheres"};
  ChapterOptions options;
  options.common.output = "ch03_spheres.png";
  add_program_options(app, options);
  app.add_option("--depth", options.max_depth, "Mirror bounces after the primary ray")
      ->check(CLI::Range(0, 16))
      ->capture_default_str();
  app.add_option("--variant", options.image_variant, "Intersection used for the image")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, SphereVariant>{{"textbook", SphereVariant::textbook},
                                               {"stable", SphereVariant::stable}},
          CLI::ignore_case))
      ->default_str("stable");
  app.add_option("--scale", options.scale,
                 "Multiply every length of the scene, and the camera's eye and target, by this")
      ->check(finite_range(1e-3, 1e7))
      ->capture_default_str();
  app.add_option("--fixed-offset", options.fixed_offset,
                 "Start mirror rays this far off the surface (a fixed epsilon) instead of the "
                 "offset that scales with the hit point")
      ->check(finite_range(0.0, 1.0));
  return run_program_main(app, argc, argv, options, [&] { return run(options); });
}
