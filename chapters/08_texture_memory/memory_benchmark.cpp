// Chapter 08: every memory path measured on a scene. See memory_benchmark.h.
#include "memory_benchmark.h"

#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "benchmark.h"
#include "bvh_build.h"
#include "memory_trace.h"
#include "model_render.h"
#include "obj_loader.h"
#include "reference.h"
#include "rt/device_buffer.h"
#include "rt/timer.h"

namespace rt::ch08 {
namespace {

using ch07::RayType;

// Hits that are not bit for bit the same: t's bits or the triangle.
long long count_differing(std::span<const MeshHit> a, std::span<const MeshHit> b) {
  if (a.size() != b.size()) return static_cast<long long>(std::max(a.size(), b.size()));
  long long differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differing += std::memcmp(&a[i], &b[i], sizeof(MeshHit)) != 0 ? 1 : 0;
  return differing;
}

Query query_for(RayType type) { return type == RayType::ao ? Query::any : Query::closest; }

// One batch of rays on one backend, ready to be traced by any path.
struct Batch {
  RayType type;
  std::vector<RayF> rays;
  std::optional<DeviceBuffer<RayF>> device;
  int count() const { return static_cast<int>(rays.size()); }
};

struct Traced {
  std::vector<MeshHit> hits;
  Timing timing;
};

Traced trace(MemoryPath path, const Batch& batch, Backend backend, const Bvh& bvh,
             const PackedBvh& packed, const DeviceTrees* trees, int frames, bool timed) {
  Traced out;
  out.hits.resize(batch.rays.size());
  const Query query = query_for(batch.type);
  if (backend == Backend::gpu) {
    DeviceBuffer<MeshHit> d_hits(batch.rays.size());
    const auto launch = [&] {
      trace_rays_path_gpu(path, query, *trees, batch.device->data(), batch.count(),
                          d_hits.data());
    };
    if (timed)
      out.timing = time_on(Backend::gpu, launch, frames);
    else
      launch();
    d_hits.download(out.hits);
  } else {
    const auto run = [&] {
      trace_rays_path_cpu(path, query, bvh, packed, batch.rays, out.hits);
    };
    if (timed)
      out.timing = time_on(Backend::cpu, run, frames);
    else
      run();
  }
  return out;
}

std::string identity_text(long long differing, std::size_t count) {
  if (differing == 0) return "identical to chapter 07's hits";
  return group_digits(differing) + " of " + group_digits(static_cast<long long>(count)) +
         " hits differ from chapter 07's";
}

} // namespace

SceneFigures measure_scene(const std::string& scene_path, const MeasureOptions& o,
                           Report& report) {
  const ch05::ObjMesh obj = ch05::load_obj(scene_path);
  const ch04::Mesh& mesh = obj.geometry;
  const Bvh bvh = ch07::build_bvh(mesh, o.build);
  const PackedBvh packed = pack_bvh(bvh);
  const ch07::PinholeCamera camera = ch07::make_protocol_camera(
      ch07::protocol_view(scene_path, bvh.bounds), o.extent.width, o.extent.height);
  const float radius = ch07::scene_radius(bvh.bounds);
  SceneFigures out{
      ch07::scene_name(scene_path), static_cast<long long>(mesh.triangles.size()), {}};
  std::map<RayType, ch07::Reference> references; // float64, per ray type, made once

  for (const Backend backend : o.backends) {
    std::optional<DeviceTrees> trees;
    if (backend == Backend::gpu) {
      ch05::check_device_memory(device_tree_bytes(bvh) + std::size_t(o.extent.pixel_count()) *
                                                             2 *
                                                             (sizeof(RayF) + sizeof(MeshHit)),
                                out.scene);
      bool textures = false;
      for (const MemoryPath p : o.paths) textures = textures || p == MemoryPath::texture;
      trees.emplace(bvh, packed, textures);
    }
    const DeviceTrees* d_trees = trees ? &*trees : nullptr;
    // Chapter 07's primary hits on this backend: the secondary rays start from them.
    Batch primary{RayType::primary, ch07::camera_rays_cpu(camera), {}};
    if (trees) primary.device.emplace(std::span<const RayF>(primary.rays));
    const Traced primary_hits =
        trace(MemoryPath::global, primary, backend, bvh, packed, d_trees, o.frames, false);

    for (const RayType type : o.ray_types) {
      Batch secondary{type, {}, {}};
      if (type != RayType::primary) {
        secondary.rays =
            ch07::secondary_rays_cpu(type, mesh, primary_hits.hits, camera, radius).rays;
        if (trees) secondary.device.emplace(std::span<const RayF>(secondary.rays));
      }
      const Batch& batch = type == RayType::primary ? primary : secondary;
      std::vector<MeshHit> secondary_hits; // chapter 07's, for secondary rays
      if (type != RayType::primary)
        secondary_hits =
            trace(MemoryPath::global, batch, backend, bvh, packed, d_trees, o.frames, false)
                .hits;
      const std::vector<MeshHit>& chapter07 =
          type == RayType::primary ? primary_hits.hits : secondary_hits;
      if (o.reference_rays > 0 && type != RayType::ao && !references.contains(type))
        references[type] = ch07::trace_reference(mesh, batch.rays, o.reference_rays);

      for (const MemoryPath path : o.paths) {
        if (!runs_on(path, backend)) continue;
        const Traced traced = trace(path, batch, backend, bvh, packed, d_trees, o.frames, true);
        const long long differing = count_differing(traced.hits, chapter07);
        const double mrays = batch.rays.empty()
                                 ? 0.0
                                 : double(batch.rays.size()) / (traced.timing.median_ms * 1e3);
        ReportRow row{out.scene + ", " + ch07::to_string(type) + ", " + to_string(path),
                      to_string(backend),
                      traced.timing.median_ms,
                      mrays,
                      identity_text(differing, batch.rays.size()),
                      {{"rays", double(batch.rays.size())},
                       {"mrays_per_s", mrays},
                       {"differing_from_ch07", double(differing)}}};
        if (references.contains(type))
          row.error += "; " + ch07::error_against(references[type], traced.hits, row);
        if (backend == Backend::gpu) {
          const int registers = path_kernel_registers(path, query_for(type));
          row.error += "; " + std::to_string(registers) + " regs";
          row.metrics.emplace_back("registers", registers);
        }
        report.add_row(row);
        out.figures.push_back({path, type, backend, mrays, differing});
        out.differing += differing;
      }

      // The primary rays made in the kernel itself, with the camera and the tree as kernel
      // parameters or in __constant__ memory.
      if (type == RayType::primary && backend == Backend::gpu && o.constants) {
        for (const ConstantsIn where :
             {ConstantsIn::parameters, ConstantsIn::constant_memory}) {
          const CameraTrace camera_trace(*trees, camera, where);
          DeviceBuffer<MeshHit> d_hits(batch.rays.size());
          const Timing timing = time_on(
              Backend::gpu, [&] { camera_trace.launch(d_hits.data()); }, o.frames);
          const long long differing = count_differing(d_hits.to_host(), chapter07);
          const double mrays = double(batch.rays.size()) / (timing.median_ms * 1e3);
          report.add_row(
              {out.scene + ", primary made in the kernel, " + to_string(k_kept_path) +
                   ", camera and tree in " + to_string(where),
               "gpu",
               timing.median_ms,
               mrays,
               identity_text(differing, batch.rays.size()) + "; " +
                   std::to_string(camera_trace.registers()) + " regs",
               {{"mrays_per_s", mrays}, {"differing_from_ch07", double(differing)}}});
          out.camera_mrays[where == ConstantsIn::parameters ? 0 : 1] = mrays;
          out.differing += differing;
        }
      }
    }
  }
  return out;
}

std::string path_tables(const std::vector<SceneFigures>& scenes, const MeasureOptions& o,
                        const std::string& device) {
  if (o.backends.empty()) return {};
  const Backend backend = o.backends.front();
  std::ostringstream out;
  for (const RayType type : o.ray_types) {
    out << "\n"
        << ch07::to_string(type) << " rays, Mrays/s on " << device
        << " (in brackets: against global)\n\n| scene |";
    std::vector<MemoryPath> shown;
    for (const MemoryPath p : o.paths)
      if (runs_on(p, backend)) shown.push_back(p);
    for (const MemoryPath p : shown) out << " " << to_string(p) << " |";
    out << "\n|---|";
    for (std::size_t k = 0; k < shown.size(); ++k) out << "---|";
    out << "\n";
    for (const SceneFigures& s : scenes) {
      double global = 0;
      for (const PathFigure& f : s.figures)
        if (f.backend == backend && f.type == type && f.path == MemoryPath::global)
          global = f.mrays;
      out << "| " << s.scene << " |";
      for (const MemoryPath p : shown) {
        for (const PathFigure& f : s.figures) {
          if (f.backend != backend || f.type != type || f.path != p) continue;
          out << " " << format_fixed(f.mrays, f.mrays < 100 ? 1 : 0);
          if (global > 0) out << " (" << format_fixed(f.mrays / global, 2) << "x)";
          if (f.differing > 0) out << " DIFFERS";
        }
        out << " |";
      }
      out << "\n";
    }
  }
  if (backend == Backend::gpu && o.constants) {
    out << "\nprimary rays made in the kernel (" << to_string(k_kept_path) << "), Mrays/s on "
        << device << "\n\n| scene | rays read from memory | "
        << "kernel parameters | __constant__ memory |\n|---|---|---|---|\n";
    for (const SceneFigures& s : scenes) {
      double from_memory = 0;
      for (const PathFigure& f : s.figures)
        if (f.backend == backend && f.type == RayType::primary && f.path == k_kept_path)
          from_memory = f.mrays;
      out << "| " << s.scene << " | "
          << (from_memory > 0 ? format_fixed(from_memory, 0) : std::string("-")) << " | "
          << format_fixed(s.camera_mrays[0], 0) << " | " << format_fixed(s.camera_mrays[1], 0)
          << " |\n";
    }
  }
  return out.str();
}

} // namespace rt::ch08
