// Chapter 07 program-test cases, shared with chapters 08 to 10, whose programs speak its query
// flags: rays from inside the course's Cornell room, a ray file sent through a program, the
// command lines the tables of refused flags start from, and refusals of flags given with
// --window.
#pragma once

#include <cmath>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "ray_io.h"
#include "rt_catch.h"
#include "run_program.h"

namespace rt::testing {

// `count` rays from one point inside the Cornell room, their directions spread over the sphere.
inline std::vector<ch03::RayF> room_ray_fan(int count) {
  std::vector<ch03::RayF> rays;
  for (int i = 0; i < count; ++i) {
    const float a = 0.1f * i, b = 0.037f * i;
    rays.push_back({{0.0f, 1.0f, 0.5f}, {std::cos(a) * std::cos(b), std::sin(b), std::sin(a)}});
  }
  return rays;
}

// Runs `program` with `arguments` and --rays `ray_file` --hits `hit_file`, requires a clean
// exit and one hit per ray of the file (`rays` of them), and returns the hits.
inline std::vector<ch04::MeshHit>
hits_from_program(const HeadlessCpuProgram& program, const std::string& arguments,
                  const std::string& ray_file, const std::string& hit_file, std::size_t rays) {
  const ProgramRun run = program(arguments + " --rays " + ray_file + " --hits " + hit_file);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  std::vector<ch04::MeshHit> hits = ch07::read_hit_file(hit_file);
  REQUIRE(hits.size() == rays);
  return hits;
}

// A small valid ray file in `folder`, so that a query that is not refused would run.
inline std::string room_ray_file(const std::filesystem::path& folder) {
  const std::string path = (folder / "fan.bin").string();
  ch07::write_ray_file(path, room_ray_fan(8));
  return path;
}

// The command lines that the tables of refused flags of chapters 07 to 10 start from, and the
// files they name, in a temporary folder named after `prefix`: a ray-file query, a dump of the
// protocol's hits and a small benchmark, each of `room`.
struct QueryCommandLines {
  std::filesystem::path folder;
  std::string rays, hits, image, json; // a small valid ray file; outputs that are never written
  std::string ray_query, dump, bench;
};

inline QueryCommandLines query_command_lines(const std::string& prefix,
                                             const std::string& room) {
  QueryCommandLines q;
  q.folder = temp_folder(prefix);
  q.rays = room_ray_file(q.folder);
  q.hits = (q.folder / "flag_hits.bin").string();
  q.image = (q.folder / "flag.png").string();
  q.json = (q.folder / "flag.json").string();
  q.ray_query = "--scene " + room + " --rays " + q.rays + " --hits " + q.hits;
  q.dump = "--scene " + room + " --width 8 --height 8 --dump-hits " + q.hits;
  q.bench = "--width 8 --height 8 --frames 1 --benchmark " + room;
  return q;
}

// check_refused for `program` run with --backend cpu --window before each case's arguments
// (HeadlessCpuProgram adds --headless, which excludes --window): each is refused in one line
// before a window is asked for, with a display or without.
inline void check_refused_with_window(const std::string& program,
                                      std::span<const RefusedInput> cases) {
  for (const RefusedInput& c : cases) {
    CAPTURE(c.arguments);
    const ProgramRun run = run_command(program + " --backend cpu --window " + c.arguments);
    INFO(run.output);
    CHECK(run.exit_code == c.exit_code);
    CHECK(line_count(run.output) == 1);
    CHECK_THAT(run.output, contains(c.says));
  }
}

} // namespace rt::testing
