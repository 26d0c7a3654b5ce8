// Chapter 07, optional: our CPU traversal measured against Embree 3 (Intel's CPU ray tracer) on
// the same cores and the very same rays, with the hits of the two compared ray by ray. Built
// only where Embree is installed; nothing else in the course depends on it.
//
//   ch07_embree_compare [--width W --height H] [--threads N] [--runs N] [--json FILE]
//                       [--backend cpu] SCENE...
//
// Both tracers see one ray list per ray type: the protocol's camera rays, then the ao and
// diffuse rays made from OUR primary hits (so a primary hit where the two disagree cannot make
// the secondary lists differ). Both run the same per-ray loop on the same thread pool; only
// the call inside it differs: trace_bvh for ours, rtcIntersect1 / rtcOccluded1 for Embree.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <embree3/rtcore.h>

#include "bvh_build.h"
#include "bvh_trace.h"
#include "obj_loader.h"
#include "protocol.h"
#include "rt/backend.h"
#include "rt/cli.h"
#include "rt/error.h"
#include "rt/report.h"
#include "rt/timer.h"
#include "runner.h"
#include "traverse.h"

namespace {

using namespace rt;
using namespace rt::ch07;
using ch04::MeshHit;

struct CompareOptions {
  int width = 1920;                 // image width in pixels (primary rays: one per pixel)
  int height = 1080;                // image height in pixels
  int threads = cpu_thread_count(); // tracing threads, the same for both; Embree's build too
  int runs = 5;                     // timed runs per ray type, after one warm-up
  std::string json;                 // also write the rows as JSON here; empty: don't
  std::vector<std::string> scenes;  // OBJ files (plain or gzip'd)
  bool robust = false;              // Embree's robust mode (RTC_SCENE_FLAG_ROBUST)
};

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
// the cores the tracing gets. Our build is single-threaded (bvh_build.h), so the build times
// compare a parallel builder with a serial one; the tracing figures compare like with like.
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
// Both tracers share chapter 07's CPU loop (for_each_ray_cpu): chunks of 256 consecutive rays
// from a shared counter, on the same threads; only the call inside it differs.

struct Traced {
  std::vector<MeshHit> hits;
  Timing timing;
};

struct TracedPair {
  Traced ours, embree;
};

// Both tracers on one ray list, timed turn about: one warm-up of each, then `runs` rounds of
// ours followed by Embree's, and each figure is the median of its own runs. On a machine that
// other work shares, a burst of that work then slows samples of both tracers, not only of
// whichever happened to be running at the time.
template <class Ours, class Embree>
TracedPair trace_both(const CompareOptions& o, std::span<const RayF> rays, Ours ours,
                      Embree embree) {
  TracedPair out;
  out.ours.hits.resize(rays.size());
  out.embree.hits.resize(rays.size());
  auto run = [&](auto& trace, std::vector<MeshHit>& hits) {
    const auto start = std::chrono::steady_clock::now();
    for_each_ray_cpu(
        rays.size(), [&](std::size_t i) { hits[i] = trace(rays[i]); }, o.threads);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
  };
  run(ours, out.ours.hits);
  run(embree, out.embree.hits);
  std::vector<double> ours_ms, embree_ms;
  for (int r = 0; r < o.runs; ++r) {
    ours_ms.push_back(run(ours, out.ours.hits));
    embree_ms.push_back(run(embree, out.embree.hits));
  }
  out.ours.timing = summarize(ours_ms);
  out.embree.timing = summarize(embree_ms);
  return out;
}

// Our triangle test is the benchmark's: the watertight one.
constexpr ch04::TriangleVariant k_variant = ch04::TriangleVariant::watertight;

// One query (closest or any hit) through both: trace_bvh, the traversal this chapter teaches,
// against rtcIntersect1 or rtcOccluded1.
template <Query kQuery>
TracedPair trace_query(const CompareOptions& o, std::span<const RayF> rays, const BvhView& tree,
                       RTCScene scene) {
  return trace_both(
      o, rays,
      [&](const RayF& ray) {
        const TraceHit h = trace_bvh<kQuery>(k_variant, tree, ray);
        return MeshHit{h.t, h.triangle};
      },
      [&](const RayF& ray) {
        return kQuery == Query::closest ? embree_closest(scene, ray) : embree_any(scene, ray);
      });
}

double mrays_per_s(std::size_t rays, const Timing& timing) {
  return rays > 0 ? double(rays) / (timing.median_ms * 1e3) : 0.0;
}

// ---------------------------------------------------------------------------------------------
// Agreement. The two tracers test triangles with different arithmetic (ours: the watertight
// test of chapter 04; Embree: a Moeller-Trumbore variant, or with --robust a Pluecker test that
// is watertight along shared edges), and visit them in different orders, so a ray that grazes
// an edge, or meets two triangles at one distance, may end on a different triangle. Such rays
// are counted, not hidden: a difference at nearly the same distance is a tie or a shared edge;
// a hit against a miss, or a hit on another surface altogether, would be a real disagreement
// worth a look.
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

void compare_scene(const std::string& path, const CompareOptions& o, RTCDevice device,
                   EmbreeErrors& errors, Report& report) {
  const std::string name = scene_name(path);
  const ch05::ObjMesh obj = ch05::load_obj(path);
  const ch04::Mesh& mesh = obj.geometry;

  auto start = std::chrono::steady_clock::now();
  const Bvh bvh = build_bvh(mesh, BuildOptions{});
  const double ours_build_s = seconds_since(start);
  start = std::chrono::steady_clock::now();
  const EmbreeScene scene = build_embree_scene(device, mesh, o.robust, errors);
  const double embree_build_s = seconds_since(start);

  const ProtocolView view = protocol_view(path, bvh.bounds);
  const PinholeCamera camera = make_protocol_camera(view, o.width, o.height);
  const float radius = scene_radius(bvh.bounds);
  const BvhView tree = bvh.view();

  std::vector<RayRow> rows;
  const std::vector<RayF> camera_rays = camera_rays_cpu(camera);
  const TracedPair primary = trace_query<Query::closest>(o, camera_rays, tree, scene.get());
  errors.check("tracing");
  rows.push_back({RayType::primary, camera_rays.size(), primary,
                  compare_closest(primary.ours.hits, primary.embree.hits)});
  // Secondary rays start where OUR primary rays hit, for both tracers.
  for (const RayType type : {RayType::ao, RayType::diffuse}) {
    const std::vector<RayF> rays =
        secondary_rays_cpu(type, mesh, primary.ours.hits, camera, radius).rays;
    if (type == RayType::ao) {
      const TracedPair ao = trace_query<Query::any>(o, rays, tree, scene.get());
      rows.push_back({type, rays.size(), ao, compare_any(ao.ours.hits, ao.embree.hits)});
    } else {
      const TracedPair diffuse = trace_query<Query::closest>(o, rays, tree, scene.get());
      rows.push_back({type, rays.size(), diffuse,
                      compare_closest(diffuse.ours.hits, diffuse.embree.hits)});
    }
    errors.check("tracing");
  }

  // The table.
  const double hit_share =
      100.0 * double(rows[1].rays) / double(std::max<std::size_t>(1, camera_rays.size()));
  std::cout
      << "\n### " << name << ": " << group_digits(static_cast<long long>(mesh.triangles.size()))
      << " triangles, " << o.width << "x" << o.height << " (" << format_fixed(hit_share, 1)
      << "% of pixels hit), " << o.threads << (o.threads == 1 ? " thread" : " threads")
      << "\n\n| rays | count | ours Mrays/s | Embree Mrays/s | ours/Embree | agreement |\n"
         "|---|---|---|---|---|---|\n";
  for (const RayRow& r : rows)
    std::cout << "| " << to_string(r.type) << " | "
              << group_digits(static_cast<long long>(r.rays)) << " | "
              << format_fixed(r.ours, 2) << " | " << format_fixed(r.embree, 2) << " | "
              << format_fixed(r.embree > 0 ? r.ours / r.embree : 0.0, 2) << " | "
              << agreement_text(r.type, r.agreement) << " |\n";
  std::cout << "\nbuild: ours " << format_fixed(ours_build_s, 3)
            << " s (binned SAH, 1 thread, SAH cost " << format_fixed(bvh.stats.sah_cost, 1)
            << "), Embree " << format_fixed(embree_build_s, 3) << " s (high quality, "
            << o.threads << (o.threads == 1 ? " thread)" : " threads)") << "\n";

  // The same figures as report rows, for --json.
  for (const RayRow& r : rows) {
    const std::string variant_name = name + ", " + to_string(r.type);
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
  const double triangles = double(mesh.triangles.size());
  report.add_row({name + ", build, ours",
                  "cpu",
                  ours_build_s * 1e3,
                  triangles / (ours_build_s * 1e6),
                  "binned SAH, 1 thread (Mtriangles/s)",
                  {{"triangles", triangles}, {"build_s", ours_build_s}}});
  report.add_row({name + ", build, Embree",
                  "cpu",
                  embree_build_s * 1e3,
                  triangles / (embree_build_s * 1e6),
                  "high quality, " + std::to_string(o.threads) + " threads (Mtriangles/s)",
                  {{"triangles", triangles}, {"build_s", embree_build_s}}});
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 07: our CPU traversal against Embree's, same rays, same cores",
               "ch07_embree_compare"};
  CompareOptions options;
  const auto side = CLI::Range(1, rt::k_max_image_side);
  app.add_option("--width", options.width, "Image width in pixels")
      ->check(side)
      ->capture_default_str();
  app.add_option("--height", options.height, "Image height in pixels")
      ->check(side)
      ->capture_default_str();
  app.add_option("--threads", options.threads, "Tracing threads, for both (and Embree's build)")
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
  app.add_option("scenes", options.scenes, "OBJ files (plain or gzip'd)")
      ->required()
      ->check(CLI::ExistingFile);
  return run_main(app, argc, argv, [&] {
    Report report("Chapter 07: our CPU traversal against Embree " RTC_VERSION_STRING, "Mrays/s",
                  "Embree");
    report.add_context("resolution",
                       std::to_string(options.width) + "x" + std::to_string(options.height));
    report.add_context("threads", std::to_string(options.threads));
    report.add_context("hardware threads", std::to_string(std::thread::hardware_concurrency()));
    report.add_context("runs",
                       "median of " + std::to_string(options.runs) + " after 1 warm-up");
    const std::string mode = options.robust ? "per-ray API, robust mode" : "per-ray API";
    report.add_context("Embree", mode);
    std::cout << "Our tree (watertight triangle test) against Embree " RTC_VERSION_STRING " ("
              << mode << "), median of " << options.runs << " runs after 1 warm-up, "
              << options.threads << " of " << std::thread::hardware_concurrency()
              << " hardware threads\n";
    EmbreeErrors errors;
    const EmbreeDevice device = make_embree_device(options.threads, errors);
    for (const std::string& path : options.scenes)
      compare_scene(path, options, device.get(), errors, report);
    if (!options.json.empty()) report.write_json(options.json);
    return 0;
  });
}
