// Chapter 04: triangles. Renders closed meshes (an icosphere, a box) and a floor quad with
// Moller-Trumbore and with the watertight test, GPU and CPU, against a float64 reference; then
// fires a million rays from inside closed meshes straight at their vertices and edges, at the
// origin and 1e5 away, and counts the rays that leak out. With --window it opens the viewer.
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include "camera_cli.h"
#include "leak_map.h"
#include "mesh_render.h"
#include "program.h"
#include "rt/program_output.h"
#include "triangle_report.h"
#include "variant_cli.h"

namespace {

using namespace rt;
using namespace rt::ch04;
using ch03::WindowResult;

struct ChapterOptions : ch03::ProgramOptions {
  double translate = 0.0; // the scene and the camera, moved along (1, 1, 1)
  int subdivisions = 2;
  int leak_rays = 1'000'000;
  std::string leak_map; // --leak-map: where the leak test's rays leak, as a picture
  TriangleVariant image_variant = TriangleVariant::watertight;
};

CameraSpec moved(CameraSpec camera, Vec3d offset) {
  camera.eye += offset;
  camera.target += offset;
  return camera;
}

std::string describe_scene(const TriangleScene& scene, double translate) {
  std::ostringstream text;
  text << scene.mesh.triangles.size() << " triangles (icosphere, box, floor quad)";
  if (translate != 0.0) text << ", moved by " << translate << " on x, y, z";
  return text.str();
}

int run(const ChapterOptions& options) {
  ch03::validate_camera(options.camera);
  if (!options.leak_map.empty()) check_image_path(options.leak_map);
  const Backend backend = resolve_backend(options.common.backend, std::cout);
  const Vec3d offset{options.translate, options.translate, options.translate};
  const TriangleScene scene = make_demo_scene(options.subdivisions, offset);
  const CameraSpec camera = moved(options.camera, offset);
  Report report = start_report("Chapter 04: Moller-Trumbore and the watertight test", "Mrays/s",
                               "float64 reference (CPU)", backend);
  report.add_context("image", to_string(options.common.extent()));
  report.add_context("scene", describe_scene(scene, options.translate));
  report.add_context("leak rows", std::to_string(options.leak_rays) +
                                      " rays each from inside a closed mesh at its vertices "
                                      "and edges; ms/frame column: ms per million rays "
                                      "(GPU: the kernel alone)");

  std::optional<DeviceTriangleScene> d_scene; // uploaded for the first GPU frame
  const ch03::ProgramParts parts{
      .chapter = "ch04",
      .window_title = "triangles",
      .camera = camera,
      .render =
          [&](Backend b, const CameraSpec& spec, Extent extent, Rgba8* pixels) {
            const auto frame_camera = ch03::make_camera<float>(spec, extent);
            if (b == Backend::cpu) {
              render_triangles(b, options.image_variant, host_view(scene.mesh),
                               scene.object.data(), frame_camera, extent, pixels);
              return;
            }
            if (!d_scene) d_scene.emplace(scene);
            render_triangles(b, options.image_variant, d_scene->view(), d_scene->object(),
                             frame_camera, extent, pixels);
          },
      .window_row =
          [&](const WindowResult& shown) {
            const MeshReference reference =
                render_triangles_reference(scene, shown.camera, shown.extent());
            return ch03::window_row(
                std::string("render, ") + to_string(options.image_variant), backend, shown,
                count_differing_pixels(shown.last_screen.pixels, reference.image.pixels));
          },
      .measure =
          [&](Report& rows) {
            report_triangle_variants(backend, scene, camera, options.common.extent(),
                                     options.common.frames, options.leak_rays, rows);
          },
      .image_note = to_string(options.image_variant),
  };
  const int status = ch03::run_window_or_headless(options, backend, parts, report);
  if (!options.leak_map.empty())
    write_output_image(options.leak_map,
                       leak_map(options.image_variant, options.leak_rays, {480, 360}),
                       std::string("where rays leak, ") + to_string(options.image_variant));
  return status;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 04: Moller-Trumbore and the watertight ray/triangle test",
               "ch04_moller_trumbore"};
  ChapterOptions options;
  options.common.width = 1280;
  options.common.height = 720;
  options.common.output = "ch04_moller_trumbore.png";
  options.camera = {{0.0, 2.2, 6.5}, {0.3, 0.7, 0.0}, {0.0, 1.0, 0.0}, 40.0};
  ch03::add_program_options(app, options);
  app.add_option("--translate", options.translate,
                 "Move the scene and the camera by this much along x, y and z")
      ->check(finite_range(-1e7, 1e7))
      ->capture_default_str();
  app.add_option("--subdivisions", options.subdivisions,
                 "Icosphere subdivisions (20 * 4^n triangles)")
      ->check(CLI::Range(0, 6))
      ->capture_default_str();
  app.add_option("--leak-rays", options.leak_rays, "Rays per leak configuration")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  app.add_option("--leak-map", options.leak_map,
                 "Also write where the leak test's rays leak through --variant's test (CPU)");
  add_triangle_variant_option(app, options.image_variant);
  return ch03::run_program_main(app, argc, argv, options, [&] { return run(options); });
}
