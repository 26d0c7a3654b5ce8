// Chapter 06: a scene to shade. A triangle mesh with a palette slot per triangle, vertex
// normals for smooth shading (the file's, or computed) and lights. The built-in scene is made
// in code; any OBJ file comes in through chapter 05's loader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "camera_spec.h"
#include "lights.h"
#include "mesh_gen.h"
#include "obj_loader.h"
#include "shade.h"
#include "vertex_normals.h"

namespace rt::ch06 {

using ch03::CameraSpec;

struct ShadedScene {
  ch04::Mesh mesh;                             // positions and triangles
  std::vector<std::uint8_t> material;          // per triangle: its slot in the palette
  Palette palette;                             // albedo per slot
  std::vector<Vec3f> normals;                  // vertex normals for smooth shading
  std::vector<IndexedTriangle> normal_indices; // per triangle; empty: one normal per position
  Lights lights;
  bool lift_shadow_origins = true; // Hanika's lift for smooth shading with shadows
  std::string description; // for the report: what the scene is, where its normals came from
};

// The features a frame of `scene` uses: smooth normals and shadows as asked, point lights if
// it has any (shadows need a light to matter).
unsigned features_used(const ShadedScene& scene, bool smooth, bool shadows);

struct Bounds {
  Vec3d min, max;
  Vec3d centre() const { return (min + max) * 0.5; }
  double radius() const { return 0.5 * length(max - min); } // the benchmark's r
};

// The box around the positions that triangles use; InputError if there are no triangles.
Bounds bounds_of(const ch04::Mesh& mesh);

// This chapter's auto-framing, the benchmark protocol's for wide images: looking down -z at
// the box's centre from r / sin(half angle) away, the half angle being that of the narrower
// of the two fields of view, so the bounding sphere fills the image's height (a wide image)
// or its width (a tall one). Chapter 05's frame_bounds looks from a slanted direction instead.
// Throws InputError, naming the cause, if that eye lies beyond chapter 03's k_max_coordinate
// or rounds onto the target in float.
CameraSpec frame_bounds_down_z(const Bounds& bounds, double fov_degrees, Extent extent);

struct LightSettings {
  Vec3d direction{-0.5, 1.0, 0.7}; // towards the directional light; any length but zero
  bool point_light = true;         // a point light above and in front of the scene
  double ambient = 0.08;           // grey ambient irradiance
};

// Throws UsageError for a zero or non-finite direction or an ambient term outside [0, 1].
void validate_lights(const LightSettings& settings);

// One directional light, and the point light if asked: above, right of and in front of the
// box, at centre + r (0.9, 1.4, 0.8) (about 1.8 r away, clear of everything in the box): a
// warm light whose irradiance at the box's centre is (0.55, 0.45, 0.33). Both lights scale
// with the scene.
Lights make_lights(const Bounds& bounds, const LightSettings& settings);

// An icosphere shaded smooth with computed vertex normals, a box and a floor quad with one
// normal per face (their edges stay sharp), all scaled by `scale` about the origin. Throws
// InputError for a scale that takes the scene out of the supported range (about 1e-8 to
// 1.6e9: ch04::check_supported_range).
ShadedScene make_default_scene(int sphere_subdivisions, double scale,
                               const LightSettings& lights);
// The camera that goes with it (chapter 04's view), scaled alike.
CameraSpec default_camera(double scale);

// A lone closed icosphere of radius `scale` centred at (2, 1, -3) * scale, lit by
// make_lights(): convex, so no face that faces a light may shadow itself. Used to look for
// shadow acne at every scale.
ShadedScene make_lone_sphere(int subdivisions, double scale, const LightSettings& lights);

// A loaded OBJ file: its normals where it has them, computed ones for corners without;
// material m gets palette slot 1 + m % 7, faces without a material slot 0.
ShadedScene scene_from_obj(const ch05::ObjMesh& obj, const LightSettings& lights,
                           NormalWeighting weighting = NormalWeighting::angle);

// Bytes of scene arrays a kernel with these features reads: what the GPU backend uploads.
std::size_t scene_bytes(const ShadedScene& scene, unsigned features);

// The scene in host memory for the CPU backend; arrays the features do not read are null.
SceneView host_view(const ShadedScene& scene, unsigned features);

// An OBJ file as a shaded scene with the default lights, and `camera` framed on it (at its
// own field of view, for an image of `extent`) wherever the reader gave no eye or no target.
ShadedScene load_framed_obj(const std::string& path, CameraSpec& camera, Extent extent,
                            bool eye_given, bool target_given);

} // namespace rt::ch06
