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
#include "wavefront.h"
#include "wide_trace.h"

namespace rt::ch11 {

using ch06::KernelKind;

// megakernel: a thread per pixel, its paths traced to the end; persistent: the megakernel's
// code, but threads that stay resident and start a new path as soon as one ends (on the CPU it
// is the megakernel); wavefront: a kernel per stage of every path (wavefront.h).
enum class PathVariant { megakernel, persistent, wavefront };
const char* to_string(PathVariant variant);
const char* to_string(Strategy strategy);
const char* to_string(SamplerKind sampler);
// "megakernel" / "persistent" / "wavefront", "bsdf" / "light" / "mis" and "independent" /
// "stratified" / "sobol" / "zsobol"; anything else is a UsageError.
PathVariant parse_variant(const std::string& text);
Strategy parse_strategy(const std::string& text);
SamplerKind parse_sampler(const std::string& text);
inline constexpr SamplerKind k_samplers[] = {SamplerKind::independent, SamplerKind::stratified,
                                             SamplerKind::sobol, SamplerKind::zsobol};

struct RenderSettings {
  PathVariant variant = PathVariant::megakernel;
  KernelKind kernel = KernelKind::specialised;
  Strategy strategy = Strategy::mis;
  SamplerKind sampler = SamplerKind::independent;
  // The samples per pixel the sampler spreads evenly as one set (stratified's grid, zsobol's
  // net; samplers.h), usually the image's total; 0: 16. The independent and sobol samplers
  // need no count.
  int sampler_samples = 0;
};

// The features a scene uses: emitters when its light table has any, sky and sun when they are
// not black.
unsigned features_used(const PathScene& scene);
// "emitters, sky, sun", or "none".
std::string describe_path_features(unsigned features);

// The pixel's mean radiance times `exposure`, through a filmic curve (Narkowicz's fit of
// ACES) and the sRGB transfer function, as 8-bit pixels in the backend's memory.
void tone_map(Backend backend, const float4* sums, Extent extent, float exposure,
              Rgba8* pixels);

// The rays one sample per pixel traces: camera and bounce rays (closest hit) and shadow rays
// (any hit).
struct RayCounts {
  long long extension = 0;
  long long shadow = 0;
  long long total() const { return extension + shadow; }
};

// [listing:progressive_renderer]
// What every progressive renderer does, whatever its scene: a running sum per pixel on its
// backend, samples added to it by one of the variants, the mean read back or tone-mapped.
// This chapter's PathRenderer and a later chapter's renderer of other surfaces differ only in
// the scene they upload and the kernels they instantiate for it (accumulate, registers).
class ProgressiveRenderer {
public:
  ProgressiveRenderer(Backend backend, unsigned features);
  virtual ~ProgressiveRenderer();
  ProgressiveRenderer(const ProgressiveRenderer&) = delete;
  ProgressiveRenderer& operator=(const ProgressiveRenderer&) = delete;

  Backend backend() const { return backend_; }
  unsigned features() const { return features_; }
  // "emitters, sky", the features the specialised kernels are compiled for.
  virtual std::string describe_features() const { return describe_path_features(features_); }
  // Empties the sums for a new view; the next samples are numbered from first_sample.
  void restart(const CameraSpec& camera, Extent extent, unsigned first_sample = 0);
  // Adds `samples` samples per pixel; returns the wavefront's statistics (zeros for the other
  // variants).
  WavefrontPass add_samples(const RenderSettings& settings, int samples);
  // Adds one sample per pixel through the wavefront, counting the rays it traces; the
  // megakernel traces the same paths, so the same rays.
  RayCounts add_counted_sample(Strategy strategy);
  int samples() const { return samples_; }
  Extent extent() const { return extent_; }
  // Waits for the GPU's work (nothing on the CPU): for timing.
  void synchronize() const;
  // Registers per thread of the GPU kernel that runs `settings` (the wavefront's largest
  // stage); needs a usable GPU.
  virtual int registers(const RenderSettings& settings) const = 0;

  std::vector<float4> sums() const;         // per pixel: radiance sums and sample count
  std::vector<Vec3f> mean_radiance() const; // per pixel, row 0 at the top
  Image image(float exposure) const;
  void tone_map_into(Rgba8* pixels, float exposure) const; // backend memory
  unsigned long long non_finite() const;                   // samples dropped since restart

protected:
  // Adds `samples` samples, numbered from `first`, to sums_ by the settings' variant; a
  // wavefront pass reports its statistics (counting shadow rays with count_rays).
  virtual WavefrontPass accumulate(const RenderSettings& settings, unsigned first, int samples,
                                   bool count_rays) = 0;
  // The image's size changed: whatever was sized for the old one goes.
  virtual void resized() {}
  // The scene changed: the sums start again (the camera and first sample kept).
  void empty_sums();
  // The settings' sampler for the current image (make_sampler).
  Sampler sampler_for(const RenderSettings& settings) const;

  Backend backend_;
  unsigned features_;
  ch03::Camera<float> camera_{};
  Extent extent_{};
  BackendArray<float4> sums_;
  BackendArray<unsigned> non_finite_;
  BackendArray<unsigned> next_path_; // the persistent threads' counter
  unsigned first_sample_ = 0;
  int samples_ = 0;
};
// [/listing:progressive_renderer]

// How a renderer builds its tree: chapter 09's SAH collapse on the CPU (the fastest tree to
// trace, for a scene that stays still), or chapter 10's LBVH and parallel collapse on the
// backend (the tree a moving scene can afford every frame).
enum class TreeBuild { sah, lbvh };

// Chapter 11's renderer: Lambertian scenes (PathScene).
class PathRenderer : public ProgressiveRenderer {
public:
  PathRenderer(const PathScene& scene, Backend backend, TreeBuild build = TreeBuild::sah);
  ~PathRenderer() override;

  // The scene moved on the host: the same triangles and materials at new vertices, sent to
  // the backend. The tree is built again and the light table made again; the sums are emptied
  // (the camera and first sample kept). A scene that moves on the backend itself is
  // MovingPathRenderer's (moving_path.h). Throws InputError for another vertex count.
  void move_vertices(const std::vector<Vec3f>& vertices);
  int registers(const RenderSettings& settings) const override;

protected:
  // A renderer whose scene lives elsewhere, in arrays on the backend that the derived class
  // owns and points view_ at (MovingPathRenderer, moving_path.h): nothing is built or
  // uploaded here.
  PathRenderer(Backend backend, unsigned features);

  PathSceneView view_{}; // what the kernels read

private:
  WavefrontPass accumulate(const RenderSettings& settings, unsigned first, int samples,
                           bool count_rays) override;
  void resized() override;
  void upload(); // the scene and tree to the backend, and view_ made for them

  PathScene scene_; // a copy: the host view points into it
  TreeBuild build_ = TreeBuild::sah;
  PathTree tree_;
  std::unique_ptr<struct DevicePathScene> device_;          // on the GPU backend
  std::unique_ptr<BasicWavefrontQueues<PathState>> queues_; // for the first wavefront samples
};

} // namespace rt::ch11
