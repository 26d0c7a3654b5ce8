// Chapter 11: progressive rendering. A PathRenderer owns the scene on its backend (chapter
// 09's compressed tree, the materials, the light table) and a running sum per pixel; each call
// adds samples to the sums, by the megakernel or the wavefront variant, and the image is the
// mean, tone-mapped. Moving the camera restarts the sums.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "path_trace.h"
#include "rt/backend_array.h"
#include "rt/image.h"
#include "shaded_render.h"
#include "wide_trace.h"

namespace rt::ch11 {

using ch06::KernelKind;

// megakernel: a thread per pixel, its paths traced to the end; persistent: the megakernel's
// code, but threads that stay resident and start a new path as soon as one ends (on the CPU it
// is the megakernel); wavefront: a kernel per stage of every path (wavefront.h).
enum class PathVariant { megakernel, persistent, wavefront };
const char* to_string(PathVariant variant);
const char* to_string(Strategy strategy);
// "megakernel" / "persistent" / "wavefront" and "bsdf" / "light" / "mis"; anything else is a
// UsageError.
PathVariant parse_variant(const std::string& text);
Strategy parse_strategy(const std::string& text);

struct RenderSettings {
  PathVariant variant = PathVariant::megakernel;
  KernelKind kernel = KernelKind::specialised;
  Strategy strategy = Strategy::mis;
};

// The features a scene uses: emitters when its light table has any, sky and sun when they are
// not black.
unsigned features_used(const PathScene& scene);
// "emitters, sky, sun", or "none".
std::string describe_path_features(unsigned features);

// Adds `samples` samples per pixel (indices first_sample, first_sample + 1, ...) to `sums` by
// the megakernel, specialised on `features` or with every feature compiled in.
void accumulate_megakernel(Backend backend, KernelKind kernel, unsigned features,
                           Strategy strategy, const PathSceneView& scene,
                           const ch03::Camera<float>& camera, unsigned first_sample,
                           int samples, float4* sums, unsigned* non_finite);

// The same sums by persistent threads: one launch per sample, as many threads as the GPU
// holds at once, each taking 32-path batches per warp from `next_path` (one counter in the
// backend's memory) and starting a new path whenever its last one ended. The CPU backend
// runs accumulate_megakernel.
void accumulate_persistent(Backend backend, KernelKind kernel, unsigned features,
                           Strategy strategy, const PathSceneView& scene,
                           const ch03::Camera<float>& camera, unsigned first_sample,
                           int samples, float4* sums, unsigned* non_finite,
                           unsigned* next_path);

// Registers per thread of the megakernel's GPU kernel (or the persistent one's); needs a
// usable GPU.
int megakernel_registers(KernelKind kernel, unsigned features,
                         PathVariant variant = PathVariant::megakernel);

// The pixel's mean radiance times `exposure`, through a filmic curve (Narkowicz's fit of
// ACES) and the sRGB transfer function, as 8-bit pixels in the backend's memory.
void tone_map(Backend backend, const float4* sums, Extent extent, float exposure,
              Rgba8* pixels);

class WavefrontQueues; // wavefront.h

// The rays one sample per pixel traces: camera and bounce rays (closest hit) and shadow rays
// (any hit).
struct RayCounts {
  long long extension = 0;
  long long shadow = 0;
  long long total() const { return extension + shadow; }
};

// How a renderer builds its tree: chapter 09's SAH collapse on the CPU (the fastest tree to
// trace, for a scene that stays still), or chapter 10's LBVH and parallel collapse on the
// backend (the tree a moving scene can afford every frame).
enum class TreeBuild { sah, lbvh };

class PathRenderer {
public:
  PathRenderer(const PathScene& scene, Backend backend, TreeBuild build = TreeBuild::sah);
  ~PathRenderer();
  PathRenderer(const PathRenderer&) = delete;
  PathRenderer& operator=(const PathRenderer&) = delete;

  Backend backend() const { return backend_; }
  unsigned features() const { return features_; }
  // Empties the sums for a new view; the next samples are numbered from first_sample.
  void restart(const CameraSpec& camera, Extent extent, unsigned first_sample = 0);
  // The scene moved: the same triangles and materials at new vertices. The tree is built again
  // and the light table made again; the sums are emptied (the camera and first sample kept).
  // Throws InputError for another vertex count.
  void move_vertices(const std::vector<Vec3f>& vertices);
  void add_samples(const RenderSettings& settings, int samples);
  // Adds one sample per pixel through the wavefront, counting the rays it traces; the
  // megakernel traces the same paths, so the same rays.
  RayCounts add_counted_sample(Strategy strategy);
  int samples() const { return samples_; }
  Extent extent() const { return extent_; }
  // Waits for the GPU's work (nothing on the CPU): for timing.
  void synchronize() const;

  std::vector<float4> sums() const;         // per pixel: radiance sums and sample count
  std::vector<Vec3f> mean_radiance() const; // per pixel, row 0 at the top
  Image image(float exposure) const;
  void tone_map_into(Rgba8* pixels, float exposure) const; // backend memory
  unsigned long long non_finite() const;                   // samples dropped since restart

private:
  void upload(); // the scene and tree to the backend, and view_ made for them

  PathScene scene_; // a copy: the host view points into it
  Backend backend_;
  TreeBuild build_;
  unsigned features_;
  PathTree tree_;
  std::unique_ptr<struct DevicePathScene> device_; // on the GPU backend
  PathSceneView view_{};
  ch03::Camera<float> camera_{};
  Extent extent_{};
  BackendArray<float4> sums_;
  BackendArray<unsigned> non_finite_;
  BackendArray<unsigned> next_path_;        // the persistent threads' counter
  std::unique_ptr<WavefrontQueues> queues_; // made for the first wavefront samples
  unsigned first_sample_ = 0;
  int samples_ = 0;
};

} // namespace rt::ch11
