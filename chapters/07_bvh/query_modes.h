// Chapter 07: the query flags every chapter with a tree speaks, so that any of the course's
// trees can be checked from outside on the same files (book appendix A): a model (--scene),
// a ray file in and a hit file out (--rays, --hits), the protocol's per-pixel hits of one view
// (--dump-hits, --ray-type), and the benchmark (--benchmark [SCENE...], --models). A chapter
// adds the flags, and runs the mode the command line asked for through its own tracer.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "program.h"
#include "protocol.h"
#include "runner.h"
#include "tracer.h"

namespace rt::ch07 {

struct QueryOptions {
  std::string scene_path;              // the model
  std::string rays_path, hits_path;    // --rays FILE --hits FILE
  std::string dump_hits_path;          // --dump-hits FILE
  RayType ray_type = RayType::primary; // --ray-type, with --dump-hits
  bool ray_type_given = false;
  bool benchmark = false;                    // --benchmark
  std::vector<std::string> benchmark_scenes; // its SCENE files
  std::string models_dir;                    // --models: where the benchmark set is looked for

  // --rays or --dump-hits: a query, not the chapter's own report.
  bool query() const { return !rays_path.empty() || !dump_hits_path.empty(); }
};

// Adds --scene, --rays, --hits, --dump-hits, --ray-type, --benchmark, the SCENE files and
// --models. `what_benchmark_measures` ends --benchmark's help line.
void add_query_options(CLI::App& app, QueryOptions& query,
                       const std::string& what_benchmark_measures);

// Adds --split, --leaf-size and --bins: how chapter 07's tree is built (for the image, the
// queries and the benchmark; later chapters build from it).
void add_build_options(CLI::App& app, BuildOptions& build);

// Flags that cannot apply together are refused, with one line naming them: --hits without
// --rays, --rays without --hits, --rays with --dump-hits, --ray-type without --dump-hits,
// SCENE files without --benchmark, --benchmark with a query. Call after parsing.
void check_query_options(const QueryOptions& query, const CLI::App& app);

// The benchmark's scenes: the SCENE files given, else the benchmark set in --models.
std::vector<std::string> benchmark_scenes(const QueryOptions& query);

// Runs --rays/--hits or --dump-hits with the first tracer `make` gives for the scene (closest
// hits, and any hits for --ray-type ao), on the resolved backend, and says what it wrote.
// `program` gives the camera flags that override the protocol's view for --dump-hits, and the
// image size (default 1920x1080). Returns the exit code.
int run_query(const QueryOptions& query, const ch03::ProgramOptions& program, Backend backend,
              const BuildOptions& build, TriangleVariant variant, const TracerMaker& make);

} // namespace rt::ch07
