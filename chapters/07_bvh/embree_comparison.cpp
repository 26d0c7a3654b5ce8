// Chapter 07, optional: a CPU tracer of the course against Embree 3 on the same threads and
// the very same rays. See embree_comparison.h; chapter 07's program is embree_compare.cpp.
//
// Both tracers see one ray list per ray type: the protocol's camera rays, then the ao and
// diffuse rays made from OUR primary hits (so a primary hit where the two disagree cannot make
// the secondary lists differ). Both run chapter 07's CPU loop (for_each_ray_cpu) on the CPU
// backend's threads: ours inside its Tracer::trace_cpu over the whole list, Embree's per-ray
// calls rtcIntersect1 / rtcOccluded1 in the same loop here.
#include "embree_comparison.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <embree3/rtcore.h>

#include "bvh_build.h"
#include "bvh_trace.h"
#include "obj_loader.h"
#include "protocol.h"
#include "query_modes.h"
#include "rt/backend.h"
#include "rt/cli.h"
#include "rt/error.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "runner.h"

namespace rt::ch07 {
namespace {

using ch04::MeshHit;

struct CompareOptions {
  int width = k_protocol_extent.width;   // image width in pixels (primary rays: one per pixel)
  int height = k_protocol_extent.height; // image height in pixels
  int threads = cpu_thread_count(); // tracing threads, the same for both; Embree's build too
  int runs = 5;                     // timed runs per ray type, after one warm-up
  std::string tracer;               // ours: one of the program's tracers
  std::string json;                 // also write the rows as JSON here; empty: don't
  std::vector<std::string> scenes;  // OBJ files (plain or gzip'd)
  bool robust = false;              // Embree's robust mode (RTC_SCENE_FLAG_ROBUST)
  BuildOptions build;               // our binary tree's: the SAH, or spatial splits (--split)
};

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

void check_tracer(const std::string& tracer, const EmbreeCompareProgram& program) {
  if (std::ranges::find(program.tracers, tracer) == program.tracers.end())
    throw UsageError("--tracer " + tracer + ": the tracers are " + joined(program.tracers));
}

// Our tracers run on the CPU backend's threads: cpu_thread_count(), which RT_CPU_THREADS sets
// (else every hardware thread) once for the whole process. Embree is given as many, so that
// the two compare like with like; --threads can only confirm that count, and a reader who
// wants another sets RT_CPU_THREADS, which moves both.
void check_threads(int threads) {
  if (threads == cpu_thread_count()) return;
  const std::string n = std::to_string(threads);
  throw UsageError("--threads " + n + ": both tracers run on the CPU backend's " +
                   std::to_string(cpu_thread_count()) +
                   " threads; run with RT_CPU_THREADS=" + n + " to give both " + n);
}

std::string threads_text(int threads) {
  return std::to_string(threads) + (threads == 1 ? " thread" : " threads");
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---------------------------------------------------------------------------------------------
// Embree's handles, owned. Embree reports errors through a callback (a C function: it must not
// throw); the callback keeps the first message, and check() turns it into an rt::Error after
// each step.

struct EmbreeErrors {
  std::mutex mutex;
  std::string first; // empty: no error so far

  static void callback(void* self, RTCError, const char* message) {
    auto* errors = static_cast<EmbreeErrors*>(self);
    const std::lock_guard lock(errors->mutex);
    if (errors->first.empty()) errors->first = message != nullptr ? message : "unknown error";
  }
  void check(const std::string& step) {
    const std::lock_guard lock(mutex);
    if (!first.empty()) throw Error("Embree: " + step + ": " + first);
  }
};

struct DeviceRelease {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct SceneRelease {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
struct GeometryRelease {
  void operator()(RTCGeometry geometry) const { rtcReleaseGeometry(geometry); }
};
using EmbreeDevice = std::unique_ptr<RTCDeviceTy, DeviceRelease>;
using EmbreeScene = std::unique_ptr<RTCSceneTy, SceneRelease>;
using EmbreeGeometry = std::unique_ptr<RTCGeometryTy, GeometryRelease>;

// A device whose builds use `threads` threads (Embree builds in parallel, on its own pool):
// the cores the tracing gets. Our binned SAH build runs on the CPU backend's threads, the same
// count (bvh_build.h); our spatial-split build runs on one, and the build row says which.
EmbreeDevice make_embree_device(int threads, EmbreeErrors& errors) {
  const std::string config = "threads=" + std::to_string(threads);
  EmbreeDevice device(rtcNewDevice(config.c_str()));
  if (!device)
    throw Error("Embree: cannot create a device (error " +
                std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(device.get(), &EmbreeErrors::callback, &errors);
  return device;
}

// One triangle geometry holding the mesh as it is: Embree's primitive id is then the mesh's
// triangle number, the protocol's triangle id. High build quality: Embree's SAH builder with
// spatial splits, its best tree for tracing.
EmbreeScene build_embree_scene(RTCDevice device, const ch04::Mesh& mesh, bool robust,
                               EmbreeErrors& errors) {
  EmbreeScene scene(rtcNewScene(device));
  errors.check("rtcNewScene");
  if (robust) rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene.get(), RTC_BUILD_QUALITY_HIGH);
  const EmbreeGeometry geometry(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
  errors.check("rtcNewGeometry");
  // Embree pads the buffers it allocates itself: it reads vertices with 16-byte loads.
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                              3 * sizeof(float), mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  errors.check("rtcSetNewGeometryBuffer");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    vertices[3 * v + 0] = mesh.vertices[v].x;
    vertices[3 * v + 1] = mesh.vertices[v].y;
    vertices[3 * v + 2] = mesh.vertices[v].z;
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    indices[3 * t + 0] = static_cast<unsigned>(mesh.triangles[t].v0);
    indices[3 * t + 1] = static_cast<unsigned>(mesh.triangles[t].v1);
    indices[3 * t + 2] = static_cast<unsigned>(mesh.triangles[t].v2);
  }
  rtcCommitGeometry(geometry.get());
  rtcAttachGeometry(scene.get(), geometry.get()); // geometry id 0; the scene holds a reference
  rtcCommitScene(scene.get());                    // the build
  errors.check("building the scene");
  return scene;
}

// ---------------------------------------------------------------------------------------------
// One ray through Embree's per-ray API, answered as our hit record.

void to_embree(const RayF& r, RTCRay& ray) {
  ray.org_x = r.origin.x;
  ray.org_y = r.origin.y;
  ray.org_z = r.origin.z;
  ray.dir_x = r.direction.x;
  ray.dir_y = r.direction.y;
  ray.dir_z = r.direction.z;
  ray.tnear = r.tmin;
  ray.tfar = r.tmax;
  ray.time = 0.0f;
  ray.mask = ~0u; // Debian's Embree is built with ray masks: an all-ones mask sees everything
  ray.id = 0;
  ray.flags = 0;
}

MeshHit embree_closest(RTCScene scene, const RayF& r) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query;
  to_embree(r, query.ray);
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
  return {query.ray.tfar, static_cast<int>(query.hit.primID)};
}

// Any hit: Embree says only whether there is one (tfar becomes -inf), not where or on what.
MeshHit embree_any(RTCScene scene, const RayF& r) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay query;
  to_embree(r, query);
  rtcOccluded1(scene, &context, &query);
  return query.tfar < 0.0f ? MeshHit{0.0f, 0} : MeshHit{};
}

// ---------------------------------------------------------------------------------------------
// Both tracers in chapter 07's CPU loop (for_each_ray_cpu): chunks of consecutive rays from a
// shared counter, on the CPU backend's threads. Ours runs it inside its trace_cpu, over the
// whole list as every program of the course traces; Embree's per-ray calls run in it here.

struct Traced {
  std::vector<MeshHit> hits;
  Timing timing;
};

struct TracedPair {
  Traced ours, embree;
};

void trace_embree(Query query, RTCScene scene, std::span<const RayF> rays,
                  std::span<MeshHit> hits) {
  for_each_ray_cpu(rays.size(), [&](std::size_t i) {
    hits[i] =
        query == Query::closest ? embree_closest(scene, rays[i]) : embree_any(scene, rays[i]);
  });
}

// Both tracers on one ray list, timed turn about: one warm-up of each, then `runs` rounds of
// ours followed by Embree's, and each figure is the median of its own runs. On a machine that
// other work shares, a burst of that work then slows samples of both tracers, not only of
// whichever happened to be running at the time.
TracedPair trace_both(Query query, std::span<const RayF> rays, const Tracer& ours,
                      RTCScene scene, int runs) {
  TracedPair out;
  out.ours.hits.resize(rays.size());
  out.embree.hits.resize(rays.size());
  const auto run_ours = [&] { ours.trace_cpu(query, rays, out.ours.hits); };
  const auto run_embree = [&] { trace_embree(query, scene, rays, out.embree.hits); };
  const auto timed_ms = [](const auto& run) {
    const auto start = std::chrono::steady_clock::now();
    run();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
  };
  timed_ms(run_ours);
  timed_ms(run_embree);
  std::vector<double> ours_ms, embree_ms;
  for (int r = 0; r < runs; ++r) {
    ours_ms.push_back(timed_ms(run_ours));
    embree_ms.push_back(timed_ms(run_embree));
  }
  out.ours.timing = summarize(ours_ms);
  out.embree.timing = summarize(embree_ms);
  return out;
}

double mrays_per_s(std::size_t rays, const Timing& timing) {
  return rays > 0 ? double(rays) / (timing.median_ms * 1e3) : 0.0;
}

// ---------------------------------------------------------------------------------------------
// Agreement. The two tracers test triangles with different arithmetic (ours: the watertight
// test of chapter 04, in every tree of the course; Embree: a Moeller-Trumbore variant, or with
// --robust a Pluecker test that is watertight along shared edges), and visit them in different
// orders, so a ray that grazes an edge, or meets two triangles at one distance, may end on a
// different triangle. Such rays are counted, not hidden: a difference at nearly the same
// distance is a tie or a shared edge; a hit against a miss, or a hit on another surface
// altogether, would be a real disagreement worth a look.
struct Agreement {
  long long rays = 0;
  long long differ = 0;       // rays whose answer differs
  long long same_t = 0;       // of those: both hit, |t_ours - t_embree| <= 1e-5 t
  long long only_ours = 0;    // of those: ours hits, Embree misses
  long long only_embree = 0;  // of those: Embree hits, ours misses
  double max_relative_dt = 0; // where both name the same triangle: the largest |dt| / t
};

constexpr double k_same_t = 1e-5; // relative: distances agree to ~80 float ulps

Agreement compare_closest(std::span<const MeshHit> ours, std::span<const MeshHit> embree) {
  Agreement a;
  a.rays = static_cast<long long>(ours.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    const MeshHit o = ours[i], e = embree[i];
    const bool o_hit = o.triangle >= 0, e_hit = e.triangle >= 0;
    const double dt = std::abs(double(o.t) - double(e.t));
    if (o.triangle == e.triangle) {
      if (o_hit && o.t > 0.0f) a.max_relative_dt = std::max(a.max_relative_dt, dt / o.t);
      continue;
    }
    ++a.differ;
    if (o_hit != e_hit)
      ++(o_hit ? a.only_ours : a.only_embree);
    else if (dt <= k_same_t * double(o.t))
      ++a.same_t;
  }
  return a;
}

// Any hit: only "occluded or not" is an answer; which triangle was found first is not.
Agreement compare_any(std::span<const MeshHit> ours, std::span<const MeshHit> embree) {
  Agreement a;
  a.rays = static_cast<long long>(ours.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    const bool o_hit = ours[i].triangle >= 0, e_hit = embree[i].triangle >= 0;
    if (o_hit == e_hit) continue;
    ++a.differ;
    ++(o_hit ? a.only_ours : a.only_embree);
  }
  return a;
}

// ---------------------------------------------------------------------------------------------
// One scene: both builds, three ray types, one Markdown table.

struct RayRow {
  RayType type;
  std::size_t rays = 0;
  double ours = 0, embree = 0; // Mrays/s
  Timing ours_timing, embree_timing;
  Agreement agreement;

  RayRow(RayType ray_type, std::size_t count, const TracedPair& traced, const Agreement& a)
      : type(ray_type), rays(count), ours(mrays_per_s(count, traced.ours.timing)),
        embree(mrays_per_s(count, traced.embree.timing)), ours_timing(traced.ours.timing),
        embree_timing(traced.embree.timing), agreement(a) {}
};

std::string agreement_text(RayType type, const Agreement& a) {
  const std::string misses = group_digits(a.only_ours) + " missed by Embree only, " +
                             group_digits(a.only_embree) + " by ours only";
  if (type == RayType::ao)
    return group_digits(a.differ) + " of " + group_digits(a.rays) +
           " differ on hit or miss: " + misses;
  const long long elsewhere = a.differ - a.same_t - a.only_ours - a.only_embree;
  return group_digits(a.differ) + " of " + group_digits(a.rays) +
         " ids differ: " + group_digits(a.same_t) + " at the same t, " +
         group_digits(elsewhere) + " at another t, " + misses + "; same id: max rel dt " +
         format_scientific(a.max_relative_dt);
}

// One scene's figures: both builds, and one row per ray type.
struct SceneComparison {
  std::string name;
  long long triangles = 0;
  std::size_t camera_rays = 0;
  std::vector<RayRow> rows; // primary, ao, diffuse
  OursOnScene ours;
  double embree_build_s = 0;
};

SceneComparison compare_scene(const std::string& path, const CompareOptions& o,
                              const EmbreeCompareProgram& program, RTCDevice device,
                              EmbreeErrors& errors) {
  SceneComparison out;
  out.name = scene_name(path);
  const ch05::ObjMesh obj = ch05::load_obj(path);
  const ch04::Mesh& mesh = obj.geometry;
  out.triangles = static_cast<long long>(mesh.triangles.size());

  // Chapter 07's SAH tree frames the protocol's camera; the program's tracer may read it too.
  const Bvh bvh = build_bvh(mesh, o.build);
  const ProtocolView view = protocol_view(path, bvh.bounds);
  const PinholeCamera camera = make_protocol_camera(view, o.width, o.height);
  const float radius = scene_radius(bvh.bounds);
  out.ours =
      program.make_ours(o.tracer, TracerScene{out.name, mesh, bvh, camera, Backend::cpu});
  const Tracer& ours = out.ours.tracer;
  if (!ours.trace_cpu) throw Error(ours.name + " has no CPU path to compare");
  const auto start = std::chrono::steady_clock::now();
  const EmbreeScene scene = build_embree_scene(device, mesh, o.robust, errors);
  out.embree_build_s = seconds_since(start);

  const std::vector<RayF> camera_rays = camera_rays_cpu(camera);
  out.camera_rays = camera_rays.size();
  const TracedPair primary = trace_both(Query::closest, camera_rays, ours, scene.get(), o.runs);
  errors.check("tracing");
  out.rows.push_back({RayType::primary, camera_rays.size(), primary,
                      compare_closest(primary.ours.hits, primary.embree.hits)});
  // Secondary rays start where OUR primary rays hit, for both tracers.
  for (const RayType type : {RayType::ao, RayType::diffuse}) {
    const std::vector<RayF> rays =
        secondary_rays_cpu(type, mesh, primary.ours.hits, camera, radius).rays;
    if (type == RayType::ao) {
      const TracedPair ao = trace_both(Query::any, rays, ours, scene.get(), o.runs);
      out.rows.push_back({type, rays.size(), ao, compare_any(ao.ours.hits, ao.embree.hits)});
    } else {
      const TracedPair diffuse = trace_both(Query::closest, rays, ours, scene.get(), o.runs);
      out.rows.push_back({type, rays.size(), diffuse,
                          compare_closest(diffuse.ours.hits, diffuse.embree.hits)});
    }
    errors.check("tracing");
  }
  return out;
}

// One Markdown table per scene, and the builds under it.
void print_table(const SceneComparison& c, const CompareOptions& o) {
  const double hit_share = // the ao rays: one per primary hit
      100.0 * double(c.rows[1].rays) / double(std::max<std::size_t>(1, c.camera_rays));
  std::cout << "\n### " << c.name << ": " << group_digits(c.triangles) << " triangles, "
            << o.width << "x" << o.height << " (" << format_fixed(hit_share, 1)
            << "% of pixels hit), " << threads_text(o.threads) << "\n\n";
  std::cout << "| rays | count | ours Mrays/s | Embree Mrays/s | ours/Embree | agreement |\n"
               "|---|---|---|---|---|---|\n";
  for (const RayRow& r : c.rows)
    std::cout << "| " << to_string(r.type) << " | "
              << group_digits(static_cast<long long>(r.rays)) << " | "
              << format_fixed(r.ours, 2) << " | " << format_fixed(r.embree, 2) << " | "
              << format_fixed(r.embree > 0 ? r.ours / r.embree : 0.0, 2) << " | "
              << agreement_text(r.type, r.agreement) << " |\n";
  std::cout << "\nbuild: ours " << format_fixed(c.ours.build_ms / 1e3, 3) << " s ("
            << c.ours.build << ", " << c.ours.cost << "), Embree "
            << format_fixed(c.embree_build_s, 3) << " s (high quality, "
            << threads_text(o.threads) << ")\n";
}

// The same figures as report rows, for --json.
void add_report_rows(const SceneComparison& c, const CompareOptions& o, Report& report) {
  for (const RayRow& r : c.rows) {
    const std::string variant_name = c.name + ", " + to_string(r.type);
    report.add_row({variant_name + ", ours",
                    "cpu",
                    r.ours_timing.median_ms,
                    r.ours,
                    agreement_text(r.type, r.agreement),
                    {{"rays", double(r.rays)},
                     {"mrays_per_s", r.ours},
                     {"min_ms", r.ours_timing.min_ms},
                     {"max_ms", r.ours_timing.max_ms},
                     {"ratio_to_embree", r.embree > 0 ? r.ours / r.embree : 0.0},
                     {"differ", double(r.agreement.differ)},
                     {"same_t", double(r.agreement.same_t)},
                     {"only_ours_hits", double(r.agreement.only_ours)},
                     {"only_embree_hits", double(r.agreement.only_embree)},
                     {"max_relative_dt", r.agreement.max_relative_dt}}});
    report.add_row({variant_name + ", Embree",
                    "cpu",
                    r.embree_timing.median_ms,
                    r.embree,
                    "(the reference)",
                    {{"rays", double(r.rays)},
                     {"mrays_per_s", r.embree},
                     {"min_ms", r.embree_timing.min_ms},
                     {"max_ms", r.embree_timing.max_ms}}});
  }
  const double triangles = double(c.triangles);
  const double ours_build_s = c.ours.build_ms / 1e3;
  report.add_row({c.name + ", build, ours",
                  "cpu",
                  c.ours.build_ms,
                  triangles / (ours_build_s * 1e6),
                  c.ours.build + " (Mtriangles/s)",
                  {{"triangles", triangles}, {"build_s", ours_build_s}}});
  report.add_row({c.name + ", build, Embree",
                  "cpu",
                  c.embree_build_s * 1e3,
                  triangles / (c.embree_build_s * 1e6),
                  "high quality, " + std::to_string(o.threads) + " threads (Mtriangles/s)",
                  {{"triangles", triangles}, {"build_s", c.embree_build_s}}});
}

} // namespace

int run_embree_compare(int argc, char** argv, const EmbreeCompareProgram& program) {
  CLI::App app{program.title, program.name};
  CompareOptions options;
  options.tracer = program.tracers.at(0);
  add_image_size_options(app, options.width, options.height);
  app.add_option("--tracer", options.tracer, "Ours: " + joined(program.tracers))
      ->capture_default_str();
  app.add_option("--threads", options.threads,
                 "Tracing threads, for both (and Embree's build): the CPU backend's, which "
                 "RT_CPU_THREADS sets; another count is refused")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  app.add_option("--runs", options.runs, "Timed runs per ray type (the median is reported)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--json", options.json, "Also write the rows as JSON to this file");
  // The other programs' --backend, so that a reader's habit is understood, not taken for a
  // scene file: Embree runs on the CPU only, so only `cpu` makes sense here.
  std::string backend = "cpu";
  app.add_option("--backend", backend, "Where to run: cpu (Embree is a CPU ray tracer)")
      ->check(CLI::IsMember({"cpu"}))
      ->capture_default_str();
  app.add_flag("--robust", options.robust,
               "Embree's robust mode: its watertight triangle test, no fast-but-inexact steps");
  // Embree's high-quality build splits triangles (spatial splits); ours may too.
  app.add_option_function<std::string>(
         "--split",
         [&options](const std::string& text) {
           options.build.method = text == "sbvh" ? SplitMethod::sbvh : SplitMethod::sah;
         },
         "How our binary tree is built: the binned SAH, or with spatial splits (sbvh)")
      ->check(CLI::IsMember({"sah", "sbvh"}))
      ->default_str("sah");
  add_split_budget_option(app, options.build);
  app.add_option("scenes", options.scenes, "OBJ files (plain or gzip'd)")
      ->required()
      ->check(CLI::ExistingFile);
  return run_main(app, argc, argv, [&] {
    check_tracer(options.tracer, program);
    check_threads(options.threads);
    check_split_budget(options.build, app);
    // A report that cannot be written is refused before the comparison, not after it.
    if (!options.json.empty()) check_report_path(options.json);
    Report report(program.report_title + " " RTC_VERSION_STRING, "Mrays/s", "Embree");
    report.add_context("resolution",
                       std::to_string(options.width) + "x" + std::to_string(options.height));
    report.add_context("ours", options.tracer);
    report.add_context("our split",
                       to_string(options.build.method) +
                           (options.build.method == SplitMethod::sbvh
                                ? ", budget " + format_fixed(options.build.split_budget, 2)
                                : std::string()));
    report.add_context("threads", threads_text(options.threads) +
                                      " for both: ours the CPU backend's (RT_CPU_THREADS, "
                                      "else the hardware's), Embree as many, its build too");
    report.add_context("hardware threads", std::to_string(std::thread::hardware_concurrency()));
    report.add_context("runs",
                       "median of " + std::to_string(options.runs) + " after 1 warm-up");
    const std::string mode = options.robust ? "per-ray API, robust mode" : "per-ray API";
    report.add_context("Embree", mode);
    // The tracer is named where the program offers a choice of them.
    const std::string ours =
        program.tracers.size() > 1 ? "Our " + options.tracer + " tree" : "Our tree";
    std::cout << ours << " (watertight triangle test) against Embree " RTC_VERSION_STRING " ("
              << mode << "), median of " << options.runs << " runs after 1 warm-up, "
              << options.threads << " of " << std::thread::hardware_concurrency()
              << " hardware threads\n";
    EmbreeErrors errors;
    const EmbreeDevice device = make_embree_device(options.threads, errors);
    for (const std::string& path : options.scenes) {
      const SceneComparison comparison =
          compare_scene(path, options, program, device.get(), errors);
      print_table(comparison, options);
      add_report_rows(comparison, options, report);
    }
    if (!options.json.empty()) report.write_json(options.json);
    return 0;
  });
}

} // namespace rt::ch07
