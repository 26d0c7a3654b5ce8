// Chapter 13: the program's run. See instancing_program.h.
#include "instancing_program.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>

#include "camera_cli.h"
#include "collapse.h"
#include "instanced_paths.h"
#include "obj_loader.h"
#include "program.h"
#include "ray_io.h"
#include "rt/backend_array.h"
#include "rt/backend_image.h"
#include "rt/error.h"
#include "rt/program_output.h"
#include "rt/timer.h"
#include "scene_loaders.h"
#include "spawn.h"
#include "two_level_scene.h"
#include "wide_trace.h"

namespace rt::ch13 {

namespace {

bool is_gltf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".gltf" || ext == ".glb";
}

// glTF's column-major 4 x 4 matrix as the course's 3 x 4 rows.
AffineD from_gltf(const std::array<double, 16>& m) {
  AffineD a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) a.m[r][c] = m[4 * c + r];
  return a;
}

InstanceScene gltf_scene(const std::string& path) {
  const ch12::GltfInstancedScene file = ch12::load_gltf_instanced_scene(path);
  InstanceScene scene;
  for (const ch12::GltfMesh& mesh : file.meshes) scene.meshes.push_back(mesh.mesh);
  for (const ch12::GltfInstance& instance : file.instances) {
    scene.placements.push_back({from_gltf(instance.world), instance.mesh});
    // The instance's colour: the base colour of its mesh's first triangle's material.
    Vec3f colour{0.7f, 0.7f, 0.7f};
    const std::vector<int>& slots = file.meshes.at(instance.mesh).material;
    if (!slots.empty() && slots[0] >= 0 &&
        static_cast<std::size_t>(slots[0]) < file.materials.size())
      colour = file.materials[slots[0]].base_color;
    scene.albedo.push_back(colour);
  }
  for (const std::string& warning : file.warnings) std::cerr << "warning: " << warning << "\n";
  scene.camera = file.camera;
  scene.description = file.description;
  return scene;
}

// Rays through every pixel of the camera.
std::vector<RayF> camera_rays(const ch03::Camera<float>& camera, Extent extent) {
  std::vector<RayF> rays;
  rays.reserve(static_cast<std::size_t>(extent.pixel_count()));
  for (int y = 0; y < extent.height; ++y)
    for (int x = 0; x < extent.width; ++x) rays.push_back(camera.ray_through_pixel(x, y));
  return rays;
}

// The world triangle an instanced hit names (to_world in float, as the shading pass does).
ch04::TriangleF world_triangle(const InstanceScene& scene,
                               const std::vector<Instance>& instances, const InstanceHit& hit) {
  const Instance& instance = instances[hit.instance];
  const ch04::TriangleF local = scene.meshes[instance.mesh].triangle(hit.triangle);
  const Affine& m = instance.to_world;
  return {m.point(local.v0), m.point(local.v1), m.point(local.v2)};
}

// Diffuse rays: from every primary hit, a cosine-distributed direction about the normal faced
// to the camera (the benchmark protocol's third kind of ray).
std::vector<RayF> diffuse_rays(const InstanceScene& scene,
                               const std::vector<Instance>& instances,
                               std::span<const RayF> primary,
                               std::span<const InstanceHit> hits) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<RayF> rays;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (hits[i].instance < 0) continue;
    const ch04::TriangleF t = world_triangle(scene, instances, hits[i]);
    const Vec3f p = t.v0 * (1.0f - hits[i].u - hits[i].v) + t.v1 * hits[i].u + t.v2 * hits[i].v;
    Vec3f n = normalize(cross(t.v1 - t.v0, t.v2 - t.v0));
    if (!(length(n) > 0.5f)) continue;
    if (dot(n, primary[i].direction) > 0.0f) n = -n;
    const Vec3f helper = std::abs(n.x) > 0.5f ? Vec3f{0, 1, 0} : Vec3f{1, 0, 0};
    const Vec3f s = normalize(cross(helper, n)), b = cross(n, s);
    const float r = std::sqrt(unit(random)),
                phi = 2.0f * std::numbers::pi_v<float> * unit(random);
    const Vec3f d = s * (r * std::cos(phi)) + b * (r * std::sin(phi)) +
                    n * std::sqrt(std::max(0.0f, 1.0f - r * r));
    rays.push_back({ch03::offset_ray_origin(p, n), d});
  }
  return rays;
}

// The rays' hits through both levels on the backend, and their time (median of the protocol).
struct Traced {
  std::vector<InstanceHit> hits;
  Timing timing;
};
Traced trace_timed(const TwoLevelScene& scene, Query query, std::span<const RayF> rays,
                   int frames) {
  const Backend backend = scene.backend();
  BackendArray<RayF> d_rays(backend, rays);
  BackendArray<InstanceHit> d_hits(backend, rays.size());
  const int count = static_cast<int>(rays.size());
  Traced out;
  out.timing = time_on(
      backend, [&] { trace_rays(scene, query, d_rays.data(), count, d_hits.data()); }, frames);
  out.hits = d_hits.to_host();
  return out;
}

// The same rays through the flattened scene's one tree (chapter 09's 4-wide packed tree).
struct FlatTraced {
  std::vector<ch04::MeshHit> hits;
  Timing timing;
};
FlatTraced trace_flat(Backend backend, const ch09::Wide4PackedBvh& tree, Query query,
                      std::span<const RayF> rays, int frames) {
  FlatTraced out;
  out.hits.resize(rays.size());
  if (backend == Backend::cpu) {
    out.timing = time_on(
        backend, [&] { ch09::trace_wide_cpu(query, tree.view(), rays, std::span(out.hits)); },
        frames);
    return out;
  }
  const ch09::DeviceWideTree<ch09::WideNode<4>, ch09::PackedTriangles> d_tree(tree);
  DeviceBuffer<RayF> d_rays(rays);
  DeviceBuffer<ch04::MeshHit> d_hits(rays.size());
  const int count = static_cast<int>(rays.size());
  out.timing = time_on(
      backend,
      [&] { ch09::trace_wide_gpu(query, d_tree.view(), d_rays.data(), count, d_hits.data()); },
      frames);
  d_hits.download(out.hits);
  return out;
}

// How the two traces agree: the same flattened triangle, or both a miss; where they differ,
// whether the instanced t is within a relative 1e-4 of the flat one (a different triangle at
// the same place: an edge, or two surfaces that touch).
struct Agreement {
  long long same = 0, near = 0, differ = 0;
};
Agreement compare_hits(std::span<const InstanceHit> instanced,
                       std::span<const ch04::MeshHit> flat,
                       const std::vector<long long>& first_triangle) {
  Agreement a;
  for (std::size_t i = 0; i < instanced.size(); ++i) {
    const InstanceHit& h = instanced[i];
    const long long id = h.instance < 0 ? -1 : first_triangle[h.instance] + h.triangle;
    if (id == flat[i].triangle)
      ++a.same;
    else if (h.instance >= 0 && flat[i].triangle >= 0 &&
             std::abs(h.t - flat[i].t) <= 1e-4f * std::max(1.0f, flat[i].t))
      ++a.near;
    else
      ++a.differ;
  }
  return a;
}

std::string agreement_text(const Agreement& a, long long rays) {
  return group_digits(a.same) + " of " + group_digits(rays) +
         " rays hit the same triangle as "
         "the flattened tree, " +
         group_digits(a.near) + " another at the same t, " + group_digits(a.differ) + " differ";
}

// [listing:two_level_work]
// What a ray costs, counted on the CPU over every `stride`-th ray: top-level nodes, instances
// entered (each a move to its space and a walk of its mesh's tree) and the bottom-level nodes
// and triangles of those walks. The GPU runs the same walk, so the counts explain its times.
struct TwoLevelWork {
  double top_nodes = 0, instances = 0, bottom_nodes = 0, triangles = 0;
};
TwoLevelWork count_work(const TwoLevelView& host_view, TopLayout top,
                        std::span<const RayF> rays, int stride) {
  TwoLevelWork work;
  long long counted = 0;
  for (std::size_t i = 0; i < rays.size(); i += stride) {
    TwoLevelCounters c;
    with_top_layout(top, [&](auto layout) {
      trace_two_level<Query::closest, decltype(layout)::value>(host_view, rays[i], 0xffffffffu,
                                                               c);
    });
    work.top_nodes += double(c.top_nodes);
    work.instances += double(c.instances);
    work.bottom_nodes += double(c.bottom.nodes);
    work.triangles += double(c.bottom.triangles);
    ++counted;
  }
  const double n = double(std::max<long long>(1, counted));
  return {work.top_nodes / n, work.instances / n, work.bottom_nodes / n, work.triangles / n};
}
// [/listing:two_level_work]

std::string work_text(const TwoLevelWork& w) {
  return "per ray: " + format_fixed(w.top_nodes, 1) + " top-level nodes, " +
         format_fixed(w.instances, 2) + " instances entered, " +
         format_fixed(w.bottom_nodes, 1) + " nodes and " + format_fixed(w.triangles, 1) +
         " triangles below";
}

// [listing:flattened_ids]
// Hits as a hit file holds them (chapter 07's format): each instance's triangles numbered after
// those of the instances before it, the order in which flattening concatenates them (and
// chapter 12's glTF loader meets them), so that the file can be checked against a flat tree.
// An int32 id numbers at most 2^31 - 1 triangles as placed; a larger scene is refused.
void write_flattened_hits(const InstanceScene& scene, std::span<const InstanceHit> traced,
                          const std::string& path) {
  long long total = 0;
  std::vector<long long> first;
  for (const Placement& p : scene.placements) {
    first.push_back(total);
    total += static_cast<long long>(scene.meshes[p.mesh].triangles.size());
  }
  if (total > std::numeric_limits<int>::max())
    throw InputError("the scene has " + group_digits(total) +
                     " triangles as placed: a hit file's int32 triangle id cannot number them");
  std::vector<ch04::MeshHit> hits(traced.size());
  for (std::size_t i = 0; i < traced.size(); ++i)
    if (traced[i].instance >= 0)
      hits[i] = {traced[i].t, static_cast<int>(first[traced[i].instance] + traced[i].triangle)};
  ch07::write_hit_file(path, hits);
  std::cout << "wrote " << path << " (" << group_digits(long(traced.size()))
            << " hits; triangles numbered instance by instance, " << group_digits(total)
            << " in all)\n";
}
// [/listing:flattened_ids]

} // namespace

InstanceScene make_scene(const InstancingOptions& options, std::vector<Spin>& spins) {
  spins.clear();
  if (!options.scene_path.empty() && is_gltf(options.scene_path))
    return gltf_scene(options.scene_path);
  ch04::Mesh tree;
  std::string name;
  if (options.small) {
    tree = ch04::make_icosphere(2, {0.0, 1.0, 0.0}, 1.0);
    name = "icosphere";
  } else {
    const std::string path = options.scene_path.empty()
                                 ? std::string(RT_ASSETS_DIR) + "/torus_knot_100k.obj.gz"
                                 : options.scene_path;
    tree = ch05::load_obj(path).geometry;
    name = std::filesystem::path(path).filename().string();
  }
  Forest forest = make_forest(tree, options.instances, options.seed, options.spin);
  spins = forest.spins;
  forest.scene.description += " (" + name + ")";
  return forest.scene;
}

int run_instancing(const InstancingOptions& options, Backend backend) {
  std::vector<Spin> spins;
  const InstanceScene scene = make_scene(options, spins);
  const BottomLevel bottom = build_bottom_level(scene.meshes, options.open_levels);
  TwoLevelScene two_level(backend, scene, bottom, spins, options.top);
  if (!options.rays_path.empty()) { // a ray file through both levels
    const std::vector<RayF> rays = ch07::read_ray_file(options.rays_path);
    write_flattened_hits(scene, trace_timed(two_level, Query::closest, rays, 1).hits,
                         options.hits_path);
    return 0;
  }

  long long placed = 0;
  for (const Placement& p : scene.placements)
    placed += static_cast<long long>(scene.meshes[p.mesh].triangles.size());
  const Extent extent = options.common.extent();
  ch03::CameraSpec spec = scene.camera.value_or(options.camera);
  if (options.eye_given) spec.eye = options.camera.eye;
  if (options.target_given) spec.target = options.camera.target;
  if (options.fov_given) spec.fov_degrees = options.camera.fov_degrees;
  ch03::validate_camera(spec);
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, extent);
  if (!options.dump_hits_path
           .empty()) { // the view's camera rays, or diffuse rays from their hits
    const std::vector<RayF> primary = camera_rays(camera, extent);
    const Traced primary_hits = trace_timed(two_level, Query::closest, primary, 1);
    if (options.ray_type == "primary") {
      write_flattened_hits(scene, primary_hits.hits, options.dump_hits_path);
    } else {
      const std::vector<RayF> diffuse =
          diffuse_rays(scene, make_instances(scene), primary, primary_hits.hits);
      write_flattened_hits(scene, trace_timed(two_level, Query::closest, diffuse, 1).hits,
                           options.dump_hits_path);
    }
    return 0;
  }

  Report report = start_report("Chapter 13: instancing, two-level trees", "Mrays/s",
                               "the same scene flattened into one tree (chapter 09's 4-wide "
                               "packed), where it fits",
                               backend);
  report.add_context("scene", scene.description);
  report.add_context("instances", group_digits(long(scene.placements.size())) + ", as " +
                                      group_digits(two_level.entry_count()) +
                                      " top-level entries (--open " +
                                      std::to_string(options.open_levels) + ")");
  long long stored = 0;
  for (const ch04::Mesh& mesh : scene.meshes)
    stored += static_cast<long long>(mesh.triangles.size());
  report.add_context("triangles stored / as placed",
                     group_digits(stored) + " / " + group_digits(placed));
  report.add_context("image", to_string(extent));
  report.add_context(
      "top level", options.top == TopLayout::binary
                       ? "binary (chapter 10's LBVH), chapter 09's walk at each instance"
                   : options.top == TopLayout::nested
                       ? "4-wide (chapter 10's LBVH, collapsed in parallel by the depth rule), "
                         "chapter 09's walk at each level, nested"
                       : "4-wide (chapter 10's LBVH, collapsed in parallel by the depth rule), "
                         "both levels in one loop");
  report.add_context("memory", "bottom level " +
                                   format_fixed(two_level.bottom_bytes() / 1e6, 2) +
                                   " MB, top level and instances " +
                                   format_fixed(two_level.top_bytes() / 1e6, 2) + " MB");
  const auto window_start = std::chrono::steady_clock::now();
  const auto measure = [&](Report& rows) {
    const int frames = options.common.frames;
    const double pixels = double(extent.pixel_count());

    // The top level, built again over the same boxes.
    const Timing top = time_on(
        backend, [&] { two_level.build_top(); }, frames);
    rows.add_row({"top-level build (LBVH over instance boxes)",
                  to_string(backend),
                  top.median_ms,
                  double(two_level.entry_count()) / top.median_ms / 1e3,
                  group_digits(two_level.entry_count()) + " entries (M entries/s)",
                  {{"entries", double(two_level.entry_count())}}});

    // The shaded image: primary rays and shadow rays.
    BackendArray<Rgba8> d_pixels(backend, static_cast<std::size_t>(extent.pixel_count()));
    const Timing shaded = time_on(
        backend, [&] { render_shaded(two_level, camera, extent, d_pixels.data()); }, frames);
    rows.add_row({"shaded frame: primary + shadow rays",
                  to_string(backend),
                  shaded.median_ms,
                  pixels / shaded.median_ms / 1e3,
                  format_fixed(1000.0 / shaded.median_ms, 1) + " fps (Mpixels/s)",
                  {{"fps", 1000.0 / shaded.median_ms}}});

    // The moving frame: every tree turned, the top level rebuilt, the frame shaded.
    if (!spins.empty()) {
      double seconds = 0.0;
      const Timing moving = time_on(
          backend,
          [&] {
            seconds += 1.0 / 60.0;
            two_level.move(seconds);
            render_shaded(two_level, camera, extent, d_pixels.data());
          },
          frames);
      rows.add_row({"moving frame: instances moved, top level rebuilt, shaded",
                    to_string(backend),
                    moving.median_ms,
                    pixels / moving.median_ms / 1e3,
                    format_fixed(1000.0 / moving.median_ms, 1) + " fps (Mpixels/s)",
                    {{"fps", 1000.0 / moving.median_ms}}});
      two_level.move(0.0); // back to the still scene for the rays below
    }

    // Paths: the sky-lit Lambertian path tracer of instanced_paths.h, --spp samples a pixel.
    if (options.spp > 0) {
      BackendArray<Vec3f> d_radiance(backend, static_cast<std::size_t>(extent.pixel_count()));
      PathSettings settings;
      settings.samples = options.spp;
      const Timing paths = time_on(
          backend,
          [&] {
            render_paths(two_level, camera, extent, settings, d_radiance.data(),
                         d_pixels.data());
          },
          frames);
      rows.add_row(
          {"path traced, sky-lit: " + std::to_string(options.spp) + " samples per pixel",
           to_string(backend),
           paths.median_ms,
           pixels * options.spp / paths.median_ms / 1e3,
           format_fixed(paths.median_ms / options.spp, 3) + " ms a sample (M samples/s)",
           {{"ms_per_sample", paths.median_ms / options.spp}}});
    }

    // Primary and diffuse rays, against the flattened scene where it fits.
    const std::vector<RayF> primary = camera_rays(camera, extent);
    const Traced primary_hits = trace_timed(two_level, Query::closest, primary, frames);
    const std::vector<Instance> instances = make_instances(scene);
    const std::vector<RayF> diffuse =
        diffuse_rays(scene, instances, primary, primary_hits.hits);
    const Traced diffuse_hits = trace_timed(two_level, Query::closest, diffuse, frames);
    const bool flatten_fits = placed <= options.flat_limit;
    std::optional<Flattened> flat;
    std::optional<ch09::Wide4PackedBvh> flat_tree;
    if (flatten_fits) {
      flat = flatten(scene);
      flat_tree = ch09::pack_wide<4, ch09::PackedTriangles>(
          ch09::build_wide_layout(flat->mesh, 4, ch09::Collapse::sah));
      rows.add_context(
          "flattened",
          group_digits(placed) + " triangles in one tree of " +
              format_fixed(
                  double(flat_tree->nodes.size() * sizeof(flat_tree->nodes[0]) +
                         flat_tree->triangles.size() * sizeof(flat_tree->triangles[0])) /
                      1e6,
                  1) +
              " MB");
    } else {
      rows.add_context("flattened", "not compared: " + group_digits(placed) +
                                        " triangles as placed, above --flat-limit " +
                                        group_digits(options.flat_limit));
    }
    // The same scene on the CPU for the counts (the GPU's arrays are not the host's).
    std::optional<TwoLevelScene> counting;
    if (backend != Backend::cpu)
      counting.emplace(Backend::cpu, scene, bottom, std::vector<Spin>{}, options.top);
    const TwoLevelView host_view = counting ? counting->view() : two_level.view();
    const auto ray_rows = [&](const std::string& kind, std::span<const RayF> rays,
                              const Traced& two) {
      const TwoLevelWork work =
          count_work(host_view, options.top, rays, std::max<int>(1, int(rays.size() / 20000)));
      std::string error = "no flattened tree to compare with";
      std::vector<std::pair<std::string, double>> metrics = {
          {"top_nodes", work.top_nodes},
          {"instances", work.instances},
          {"bottom_nodes", work.bottom_nodes},
          {"triangles", work.triangles}};
      if (flat) {
        const FlatTraced one = trace_flat(backend, *flat_tree, Query::closest, rays, frames);
        const Agreement a = compare_hits(two.hits, one.hits, flat->first_triangle);
        error = agreement_text(a, long(rays.size()));
        metrics.insert(
            metrics.end(),
            {{"same", double(a.same)}, {"near", double(a.near)}, {"differ", double(a.differ)}});
        rows.add_row({kind + " rays, flattened (one tree)",
                      to_string(backend),
                      one.timing.median_ms,
                      double(rays.size()) / one.timing.median_ms / 1e3,
                      "the reference",
                      {}});
      }
      rows.add_row({kind + " rays, two levels", to_string(backend), two.timing.median_ms,
                    double(rays.size()) / two.timing.median_ms / 1e3,
                    error + "; " + work_text(work), metrics});
    };
    ray_rows("primary", primary, primary_hits);
    ray_rows("diffuse", diffuse, diffuse_hits);
  };
  ch03::ProgramParts parts{
      .chapter = "ch13",
      .window_title = "instancing",
      .camera = spec,
      // The window's frames: the forest turning (--spin) as the seconds pass on screen.
      .render =
          [&](Backend, const ch03::CameraSpec& view, Extent size, Rgba8* pixels) {
            if (options.spin != 0.0 && !spins.empty())
              two_level.move(
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - window_start)
                      .count());
            render_shaded(two_level, ch03::make_camera<float>(view, size), size, pixels);
          },
      .window_row =
          [&](const ch03::WindowResult& shown) {
            return ch03::window_fps_row("shaded frame: primary + shadow rays", backend, shown);
          },
      .measure = [&](Report& rows) { measure(rows); },
      // The headless picture: the scene still, at time 0.
      .image =
          [&] {
            two_level.move(0.0);
            return render_into_image(backend, extent, [&](Rgba8* pixels) {
              if (options.spp == 0) return render_shaded(two_level, camera, extent, pixels);
              BackendArray<Vec3f> radiance(backend,
                                           static_cast<std::size_t>(extent.pixel_count()));
              PathSettings settings;
              settings.samples = options.spp;
              render_paths(two_level, camera, extent, settings, radiance.data(), pixels);
            });
          },
  };
  return ch03::run_window_or_headless(options, backend, parts, report);
}

} // namespace rt::ch13
