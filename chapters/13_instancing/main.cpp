// Chapter 13: instancing and two-level trees. By default a forest of the course's
// ~100k-triangle model, --instances copies placed on a grid, each a transform of one mesh whose
// tree is built once; the top-level tree over the instances' boxes is chapter 10's LBVH. It
// reports the top level's build, the shaded frame (primary and shadow rays through both
// levels), the moving frame (--spin: every tree turned, the top level rebuilt) and primary and
// diffuse rays against the same scene flattened into one tree, where that fits. Other scenes
// and modes:
//   --scene FILE.obj     a forest of that mesh
//   --scene FILE.gltf    a glTF file's node graph, its meshes kept as instances
//   --small              a forest of 320-triangle icospheres (a million instances and more)
//   --rays FILE --hits FILE   a ray file through both levels; the hits' triangle ids count
//                             instance by instance, as the flattened scene numbers them
//   --dump-hits FILE [--ray-type primary|diffuse]   the view's hits, numbered the same way
#include <iostream>

#include "instance_scene.h"
#include "instancing_program.h"
#include "ray_io.h"
#include "rt/cli.h"
#include "rt/error.h"

namespace {

using namespace rt;
using namespace rt::ch13;

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 13: instancing, two-level trees over a forest or a glTF node graph",
               "ch13_instancing"};
  InstancingOptions options;
  options.common.output = "ch13_instancing.png";
  ch03::add_program_options(app, options);
  app.add_option("--scene", options.scene_path,
                 "An OBJ file (the forest's tree) or a glTF file (.gltf, .glb: its node graph, "
                 "meshes kept as instances)");
  app.add_option("--instances", options.instances, "Trees in the forest")
      ->check(CLI::Range(1, int(k_max_instances - 1)))
      ->capture_default_str();
  app.add_flag("--small", options.small, "The forest's trees are 320-triangle icospheres");
  app.add_option("--spin", options.spin,
                 "Radians a second each tree turns in the moving frame's measurement (0: none)")
      ->check(finite_range(-100.0, 100.0))
      ->capture_default_str();
  app.add_option("--spp", options.spp,
                 "Path-trace the scene under a white sky with this many samples per pixel "
                 "(chapter 11's bounces through both levels): a row of the report, and the "
                 "--output picture; 0: the shaded frame alone")
      ->check(CLI::Range(0, 65536))
      ->capture_default_str();
  app.add_option("--seed", options.seed, "The forest's layout")->capture_default_str();
  app.add_option_function<std::string>(
         "--top",
         [&](const std::string& text) {
           options.top = text == "wide"     ? TopLayout::wide
                         : text == "nested" ? TopLayout::nested
                                            : TopLayout::binary;
         },
         "The top level and its walk: binary (chapter 07's node and walk), nested (chapter "
         "09's 4-wide node, collapsed every build, and its walk, which calls the mesh's at "
         "each instance) or wide (the same node, both levels in one loop)")
      ->check(CLI::IsMember({"binary", "nested", "wide"}))
      ->default_str("wide");
  app.add_option("--open", options.open_levels,
                 "Levels an instance of a mesh of " + std::to_string(k_open_min_triangles) +
                     " triangles or more is opened into subtrees in the top level (0: one "
                     "entry per instance)")
      ->check(CLI::Range(0, k_max_open_levels))
      ->capture_default_str();
  app.add_option("--flat-limit", options.flat_limit,
                 "Flatten the scene into one tree for comparison up to this many triangles")
      ->check(CLI::Range(0, 1 << 28))
      ->capture_default_str();
  app.add_option("--rays", options.rays_path,
                 "A ray file traced through both levels (" + ch07::describe_ray_file_limits() +
                     ")");
  app.add_option("--hits", options.hits_path, "With --rays: the hit file to write");
  app.add_option(
      "--dump-hits", options.dump_hits_path,
      "The hits of the view's rays (--ray-type) to this hit file, triangles numbered "
      "instance by instance");
  app.add_option(
         "--ray-type", options.ray_type,
         "With --dump-hits: primary (the camera's rays) or diffuse (one cosine-weighted "
         "ray from each primary hit)")
      ->check(CLI::IsMember({"primary", "diffuse"}))
      ->capture_default_str();
  return ch03::run_program_main(app, argc, argv, options, [&] {
    if (options.rays_path.empty() != options.hits_path.empty())
      throw UsageError("--rays and --hits go together");
    if (!options.dump_hits_path.empty() && !options.rays_path.empty())
      throw UsageError("--dump-hits traces the view's rays: not with --rays");
    if (app.count("--ray-type") > 0 && options.dump_hits_path.empty())
      throw UsageError("--ray-type goes with --dump-hits");
    if (options.small && !options.scene_path.empty())
      throw UsageError("--small makes its own trees: not with --scene");
    const Backend backend = resolve_backend(options.common.backend, std::cout);
    return run_instancing(options, backend);
  });
}
