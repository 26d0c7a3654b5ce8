// Chapter 13: what the program runs, apart from its command line (main.cpp), so that the tests
// run the same steps: the scene made from the options, and the report of one run.
#pragma once

#include <string>

#include "instance_scene.h"
#include "program.h"
#include "rt/backend.h"
#include "two_level.h"

namespace rt::ch13 {

struct InstancingOptions : ch03::ProgramOptions {
  std::string scene_path; // --scene: an OBJ file (the forest's tree) or a glTF file
  int instances = 1000;   // --instances: the forest's trees
  bool small = false;     // --small: the trees are icospheres of 320 triangles
  double spin = 0.0;      // --spin: radians a second each tree turns (the moving frame's)
  unsigned seed = 1;      // --seed: the forest's layout
  TopLayout top = TopLayout::wide; // --top: the top level's node
  int spp = 0;         // --spp: path-traced samples per pixel (0: the shaded frame alone)
  int open_levels = 0; // --open: levels instances of large meshes are opened
  int flat_limit = 16'000'000; // --flat-limit: flatten for comparison up to this many triangles
  std::string rays_path, hits_path; // --rays, --hits
  std::string dump_hits_path;       // --dump-hits: the view's hits
  std::string ray_type = "primary"; // --ray-type: primary, or diffuse from the primary hits
};

// The scene the options describe: the glTF file's node graph, or a forest of the OBJ file's
// mesh (or of the course's model, or of icospheres with --small). `spins` gets the forest's.
InstanceScene make_scene(const InstancingOptions& options, std::vector<Spin>& spins);

// The whole run on the resolved backend: --rays/--hits, or the report with the image.
int run_instancing(const InstancingOptions& options, Backend backend);

} // namespace rt::ch13
