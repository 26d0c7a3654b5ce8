// Chapter 07: the query flags every chapter with a tree speaks, so that any of the course's
// trees can be checked from outside on the same files (book appendix A): a model (--scene),
// a ray file in and a hit file out (--rays, --hits), the protocol's per-pixel hits of one view
// (--dump-hits, --ray-type), and the benchmark (--benchmark [SCENE...], --models). A chapter
// adds the flags, and runs the mode the command line asked for through its own tracer. A flag
// that does nothing in the mode asked for is refused, in one line naming both flags.
#pragma once

#include <functional>
#include <initializer_list>
#include <span>
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

// The defaults every program with a tree (chapters 07-10) starts from: a 1280x720 image
// written to `output`, the course's ~100k-triangle model in `assets_dir` as the scene, and the
// benchmark set looked for in `models_dir`.
void set_tree_program_defaults(ch03::ProgramOptions& program, QueryOptions& query,
                               const std::string& output, const std::string& assets_dir,
                               const std::string& models_dir);

// Adds --reference-rays (rays per ray type that the float64 reference traces, every triangle
// in double) and --skip-cpu: the report options of the chapters after this one.
void add_reference_options(CLI::App& app, long long& reference_rays, bool& skip_cpu);

// Adds --split, --leaf-size and --bins: how chapter 07's tree is built (for the image, the
// queries and the benchmark; later chapters build from it).
void add_build_options(CLI::App& app, BuildOptions& build);
// --split-budget alone (add_build_options includes it), and its check: refused without
// --split sbvh, in one line.
void add_split_budget_option(CLI::App& app, BuildOptions& build);
void check_split_budget(const BuildOptions& build, const CLI::App& app);

// What a program with a tree does with its command line: one mode, picked by its flags.
enum class ProgramMode {
  report,     // the chapter's measurements and image (or, with a display, its window)
  window,     // --window: the image on screen
  image_only, // --image-only: the image alone
  rays,       // --rays FILE --hits FILE
  dump_hits,  // --dump-hits FILE
  benchmark,  // --benchmark [SCENE...]
};

ProgramMode program_mode(const QueryOptions& query, const ch03::ProgramOptions& program);

// The modes in which a flag does something.
class ModeSet {
public:
  constexpr ModeSet(std::initializer_list<ProgramMode> modes) {
    for (const ProgramMode m : modes) bits_ |= 1u << static_cast<unsigned>(m);
  }
  constexpr bool has(ProgramMode m) const { return (bits_ >> static_cast<unsigned>(m)) & 1u; }

private:
  unsigned bits_ = 0;
};

// Flags of the shaded image (the window's, --image-only's, the report's --output) ...
inline constexpr ModeSet k_image_modes{ProgramMode::report, ProgramMode::window,
                                       ProgramMode::image_only};
// ... of the chapter's own measurements alone ...
inline constexpr ModeSet k_report_modes{ProgramMode::report};
// ... and of what is traced: the measurements, the queries and the benchmark, not the image.
inline constexpr ModeSet k_traced_modes{ProgramMode::report, ProgramMode::rays,
                                        ProgramMode::dump_hits, ProgramMode::benchmark};

// A chapter's flag and the modes in which it does something; given in another, it is refused.
struct FlagModes {
  const char* flag; // "--shading"
  ModeSet modes;
};

// Refuses, in one line naming both flags, what cannot apply together: --hits without --rays,
// --rays without --hits, --rays with --dump-hits, --ray-type without --dump-hits, SCENE files
// without --benchmark, --benchmark with a query; then any flag given (the common ones, the
// camera's, the query flags, and the chapter's `chapter_flags`) that does nothing in the mode
// the command line picks, such as --json with --rays or --scene with --benchmark. Checks the
// hit files' paths before the work. Call after parsing.
void check_query_options(const QueryOptions& query, const ch03::ProgramOptions& program,
                         const CLI::App& app, std::span<const FlagModes> chapter_flags = {});

// What a chapter's --benchmark measures and prints; the rest of the mode is the same in every
// chapter (run_benchmark_mode).
struct BenchmarkMode {
  std::string title;     // the report's title
  std::string reference; // what the hits are checked against, for the report's error column
  // The chapter's runner settings (tree, triangle test, rows, checks); the image, backend and
  // frames come from the command line.
  RunnerOptions runner = protocol_runner_options();
  // The tracers measured on each scene; a maker may add rows of its own (builds) to `report`.
  std::function<std::vector<TracerMaker>(Report& report)> tracers;
  // The chapter's context lines after the runner's; may be empty.
  std::function<void(Report& report)> context = {};
  // The tables printed after the report, from the figures of every scene.
  std::function<std::string(const std::vector<SceneResult>& results,
                            const RunnerOptions& runner)>
      tables;
  std::string disagreement; // the error when a tracer's hits break its rule
};

// The benchmark protocol on the SCENE files of `query`, else on the benchmark set in --models
// (a folder holding part of the set is measured on that part, after a warning line naming the
// models missing): k_protocol_extent unless --width/--height say otherwise, --frames timed
// runs, on the resolved backend. Prints the report (and writes --json), then the chapter's
// tables; throws Error(mode.disagreement) if a tracer broke its rule or a sampled ray differed
// from brute force. Returns the exit code.
int run_benchmark_mode(const BenchmarkMode& mode, const QueryOptions& query,
                       const ch03::ProgramOptions& program, Backend backend);

// Runs --rays/--hits or --dump-hits with the first tracer `make` gives for the scene (closest
// hits, and any hits for --ray-type ao), on the resolved backend, and says what it wrote.
// `program` gives the camera flags that override the protocol's view for --dump-hits, and the
// image size (default 1920x1080). Returns the exit code.
int run_query(const QueryOptions& query, const ch03::ProgramOptions& program, Backend backend,
              const BuildOptions& build, TriangleVariant variant, const TracerMaker& make);

} // namespace rt::ch07
