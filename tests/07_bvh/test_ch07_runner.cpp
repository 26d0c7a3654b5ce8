// Chapter 07 tests of the benchmark runner: a tracer that answers wrongly is caught on every
// ray type, the two hit rules (bit for bit, up to exact ties) accept and refuse what they
// should, a tracer that makes its own camera rays is timed on primary rays only, its progress
// lines name every step, and the industry's figures are read from their data file, matched to
// a device and refused when malformed.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "anchors.h"
#include "rt/error.h"
#include "run_program.h"
#include "runner.h"

using namespace rt;
using namespace rt::ch07;
using rt::testing::contains;

namespace {

// A box open towards +z (where the protocol's auto-framed camera stands), whose every face is
// written twice (the same three vertices, a second id): the camera looks into it, secondary
// rays from its inside hit its other walls, and every hit is an exact tie of two triangles.
std::string write_twin_box(const std::filesystem::path& folder) {
  const std::string path = (folder / "twin_box.obj").string();
  std::ofstream out(path);
  for (int v = 0; v < 8; ++v)
    out << "v " << (v & 1 ? 1 : -1) << " " << (v & 2 ? 1 : -1) << " " << (v & 4 ? 1 : -1)
        << "\n";
  const int faces[10][3] = {{1, 2, 4}, {1, 4, 3}, {1, 5, 6}, {1, 6, 2}, {3, 4, 8},
                            {3, 8, 7}, {1, 3, 7}, {1, 7, 5}, {2, 6, 8}, {2, 8, 4}};
  for (int copy = 0; copy < 2; ++copy)
    for (const auto& f : faces) out << "f " << f[0] << " " << f[1] << " " << f[2] << "\n";
  return path;
}

RunnerOptions small_cpu_run() {
  RunnerOptions o;
  o.extent = {32, 18};
  o.backend = Backend::cpu;
  o.frames = 1;
  return o;
}

// Chapter 07's tree with every hit's triangle id passed through `change`.
TracerMaker changed_ids(std::string name, HitRule rule, int (*change)(int)) {
  return [=](const TracerScene& scene) {
    Tracer t = bvh_tracer(name, scene.bvh, scene);
    t.rule = rule;
    const auto trace = t.trace_cpu;
    t.trace_cpu = [trace, change](Query q, std::span<const RayF> rays,
                                  std::span<MeshHit> hits) {
      trace(q, rays, hits);
      for (MeshHit& h : hits)
        if (h.triangle >= 0) h.triangle = change(h.triangle);
    };
    return std::vector<Tracer>{t};
  };
}

int twin_of(int id) { return id < 10 ? id + 10 : id - 10; }
int miss_of(int) { return -1; }

const TracerFigure& figure(const SceneResult& r, const std::string& tracer, RayType type) {
  const TracerFigure* f = r.find(tracer, type);
  REQUIRE(f != nullptr);
  return *f;
}

} // namespace

TEST_CASE("runner: every tracer is checked against chapter 07 on every ray", "[ch07]") {
  const std::string box = write_twin_box(rt::testing::temp_folder("rt_ch07_runner"));
  Report report("runner test", "Mrays/s", "chapter 07");
  const SceneResult r =
      run_scene({box},
                {chapter07_tracers, changed_ids("twins, exact", HitRule::identical, twin_of),
                 changed_ids("twins, ties", HitRule::ties_allowed, twin_of),
                 changed_ids("blind", HitRule::ties_allowed, miss_of)},
                small_cpu_run(), report);
  for (const RayType type : {RayType::primary, RayType::ao, RayType::diffuse}) {
    CAPTURE(to_string(type));
    CHECK(figure(r, "sah", type).disagreeing == 0);
    // Swapping each hit for its twin: the same distance on another triangle. Bit for bit that
    // differs on every hit (short ao rays may find none).
    if (type != RayType::ao) CHECK(figure(r, "twins, exact", type).disagreeing > 0);
    CHECK(figure(r, "twins, ties", type).disagreeing == 0);
  }
  // A tracer that never hits is wrong wherever chapter 07 hits something.
  CHECK(figure(r, "blind", RayType::primary).disagreeing > 0);
  CHECK(r.problems > 0);
  const std::string tables =
      tracer_tables({r}, "sah", small_cpu_run(), "test device", Anchors{});
  CHECK_THAT(tables, contains("DIFFERS"));
  CHECK_THAT(tables, contains("| twin_box |"));
  bool named = false;
  for (const ReportRow& row : report.rows())
    named = named || row.variant == "twin_box, diffuse, twins, ties";
  CHECK(named);
}

TEST_CASE("runner: a tracer of camera rays only is timed on primary rays", "[ch07]") {
  const std::string box = write_twin_box(rt::testing::temp_folder("rt_ch07_runner"));
  const TracerMaker camera_maker = [](const TracerScene& scene) {
    Tracer t = bvh_tracer("camera", scene.bvh, scene);
    t.camera_rays_only = true;
    return std::vector<Tracer>{t};
  };
  Report report("runner test", "Mrays/s", "chapter 07");
  const SceneResult r = run_scene({box}, {camera_maker}, small_cpu_run(), report);
  CHECK(r.find("camera", RayType::primary) != nullptr);
  CHECK(r.find("camera", RayType::ao) == nullptr);
  CHECK(r.find("camera", RayType::diffuse) == nullptr);
  CHECK(report.rows().size() == 1);
}

TEST_CASE("runner: brute force on sampled rays and the build row", "[ch07]") {
  const std::string box = write_twin_box(rt::testing::temp_folder("rt_ch07_runner"));
  RunnerOptions o = small_cpu_run();
  o.check_rays = 64;
  o.build_rows = true;
  Report report("runner test", "Mrays/s", "brute force");
  const SceneResult r = run_scene({box}, {chapter07_tracers}, o, report);
  CHECK(r.problems == 0);
  REQUIRE(report.rows().size() == 4);
  CHECK_THAT(report.rows()[0].error, contains("sampled rays differ from brute force"));
  CHECK(report.rows()[3].variant == "twin_box, build (sah, CPU)");
  CHECK(r.triangles == 20);
}

TEST_CASE("runner: its progress lines name the scene, the ray type and the tracer", "[ch07]") {
  const std::string box = write_twin_box(rt::testing::temp_folder("rt_ch07_runner"));
  RunnerOptions o = small_cpu_run();
  std::ostringstream lines;
  o.progress = &lines;
  o.progress_period = std::chrono::milliseconds(0); // a line at every step
  Report report("runner test", "Mrays/s", "chapter 07's hits");
  run_scene({box}, {chapter07_tracers}, o, report);
  INFO(lines.str());
  for (const char* line :
       {"twin_box: loading, chapter 07's tree, ",
        "twin_box, ao rays: the rays, chapter 07's hits, the checks, ",
        "twin_box, primary rays, sah: warm-up, ", "twin_box, ao rays, sah: timed run 1 of 1, ",
        "twin_box, diffuse rays, sah: timed run 1 of 1, "})
    CHECK_THAT(lines.str(), contains(line));
}

TEST_CASE("runner: the benchmark set's folder must hold some of it", "[ch07]") {
  const std::filesystem::path empty = rt::testing::temp_folder("rt_ch07_runner_empty");
  try {
    benchmark_set(empty.string());
    FAIL("an empty folder was accepted");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), contains("tools/get-models.sh"));
    CHECK_THAT(e.what(), contains(empty.string()));
  }
}

TEST_CASE("anchors: the course's figures, matched to the GPU that ran", "[ch07]") {
  const Anchors anchors = read_anchors(RT_ANCHORS_FILE);
  const AnchorSet* h200 = anchors.for_device("NVIDIA H200");
  REQUIRE(h200 != nullptr);
  CHECK(h200->system == "OptiX 9.0");
  const AnchorFigures* conference = find_scene(h200, "conference");
  REQUIRE(conference != nullptr);
  CHECK(conference->for_type(RayType::primary) == 3606);
  CHECK(conference->for_type(RayType::diffuse) == 1349);
  const AnchorSet* h100 = anchors.for_device("NVIDIA H100 80GB HBM3");
  REQUIRE(h100 != nullptr);
  CHECK(find_scene(h100, "conference")->primary == 3700);
  CHECK(anchors.for_device("NVIDIA GeForce RTX 4090") == nullptr);
  CHECK(anchors.for_device("12 CPU threads") == nullptr);
  CHECK(find_scene(h200, "cornell_room") == nullptr);
}

TEST_CASE("anchors: a malformed file is one clear error", "[ch07]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch07_anchors");
  const auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = (folder / name).string();
    std::ofstream(path) << text;
    return path;
  };
  CHECK_THROWS_AS(read_anchors((folder / "missing.json").string()), InputError);
  CHECK_THROWS_AS(read_anchors(write("broken.json", "{\"sets\": [")), InputError);
  CHECK_THROWS_AS(read_anchors(write("no_sets.json", "{}")), InputError);
  CHECK_THROWS_AS(
      read_anchors(write("negative.json", "{\"sets\": [{\"system\": \"s\", \"device\": \"d\", "
                                          "\"scenes\": {\"x\": {\"primary\": -1}}}]}")),
      InputError);
}

TEST_CASE("summary: the share of the industry's figure on the same device", "[ch07]") {
  SceneResult r{"conference", 331179};
  r.build_ms = 200;
  r.bytes_per_triangle = 69;
  r.figures = {{"sah", RayType::primary, 1803, 69, 0},
               {"sah", RayType::ao, 3353, 69, 0},
               {"sah", RayType::diffuse, 674.6, 69, 0}};
  const Anchors anchors({{"OptiX 9.0", "NVIDIA H200", {{"conference", 3606, 3353, 1349}}}});
  const std::string table = summary_table({r}, "sah", "NVIDIA H200", anchors);
  CHECK_THAT(table,
             contains("| conference | 331 179 | 1803 (50%) | 3353 (100%) | 675 (50%) |"));
  CHECK_THAT(table, contains("share of OptiX 9.0's figure"));
  const std::string elsewhere = summary_table({r}, "sah", "NVIDIA A100", anchors);
  CHECK_THAT(elsewhere, !contains("%"));
}
