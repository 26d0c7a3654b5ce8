// Chapter 12: the progressive renderer of scenes with materials. Chapter 11's running sums and
// variants (ProgressiveRenderer), its kernels instantiated for chapter 12's scene view: the
// materials, texture coordinates, textures and compensation tables uploaded beside chapter
// 11's tree, mesh and light table.
#pragma once

#include <memory>
#include <string>

#include "material_scene.h"
#include "material_trace.h"
#include "path_render.h"

namespace rt::ch12 {

using ch11::PathVariant;
using ch11::RenderSettings;

// What a renderer reads its textures with and whether it compensates for multiple scattering.
struct MaterialOptions {
  TextureFilter filter = TextureFilter::trilinear;
  bool texture_objects = true; // the GPU's texture units; false: plain loads and the software
                               // filter, as on the CPU
  bool compensation = true;    // Kulla and Conty's lobe (energy_compensation.h)
};

// The features a scene uses: chapter 11's lights, textures when a material names one and the
// triangles have texture coordinates, specular when a material is not Lambertian.
unsigned material_features_used(const MaterialScene& scene);
// "emitters, sky, textures, specular", or "none".
std::string describe_material_features(unsigned features);

class MaterialRenderer : public ch11::ProgressiveRenderer {
public:
  MaterialRenderer(const MaterialScene& scene, Backend backend, MaterialOptions options = {});
  ~MaterialRenderer() override;

  // Another filter, texture path or compensation for the next samples (the sums are emptied).
  void set_options(const MaterialOptions& options);
  const MaterialOptions& options() const { return options_; }
  std::string describe_features() const override;
  int registers(const RenderSettings& settings) const override;
  const MaterialSceneView& view() const { return view_; }

private:
  ch11::WavefrontPass accumulate(const RenderSettings& settings, unsigned first, int samples,
                                 bool count_rays) override;
  void resized() override;
  void make_view();

  MaterialScene scene_; // a copy: the host view points into it
  MaterialOptions options_;
  ch11::PathTree tree_;
  CompensationTable compensation_;
  HostTextures host_textures_;
  std::unique_ptr<struct DeviceMaterialScene> device_; // on the GPU backend
  MaterialSceneView view_{};
  std::unique_ptr<ch11::BasicWavefrontQueues<MaterialPath>> queues_;
};

// The base colour the camera sees at each pixel's centre (no light transport): what the
// textures alone put on the screen, to measure their aliasing. With `samples` above 1, the
// mean of that many jittered points per pixel (chapter 11's pixel jitter), point-sampled: the
// supersampled reference the filters are measured against.
std::vector<Vec3f> render_base_colour(const MaterialRenderer& renderer,
                                      const CameraSpec& camera, Extent extent, int samples);

// The two samplers of visible normals (microfacet.h), timed on the backend: `threads` threads
// each draw 64 normals for hashed incident directions (cos theta_o in (0, 1]) and roughness
// (alpha in [0.001, 1)), and add up their z. Both draw the same distribution, so the two means
// agree up to noise: the measurement's check that neither was cut short.
enum class VisibleNormals { heitz, caps };
struct VisibleNormalTiming {
  double ms = 0.0;       // median of the protocol's runs
  long long samples = 0; // normals drawn per run
  double mean_z = 0.0;   // the mean z of the normals drawn
};
VisibleNormalTiming time_visible_normals(Backend backend, VisibleNormals sampler, int threads,
                                         int frames);

} // namespace rt::ch12
