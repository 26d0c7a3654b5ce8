// Chapter 11: a scene for light transport. Chapter 06's meshes lit by their own surfaces: each
// triangle has a material with a diffuse albedo (an MTL file's Kd) and an emission (its Ke),
// and the emitting triangles are the area lights. A constant sky and a sun light open scenes.
// The light table that next-event estimation samples from is built here, on the host.
#pragma once

#include <string>
#include <vector>

#include "camera_spec.h"
#include "mesh_gen.h"
#include "rt/launch.h"
#include "rt/vec.h"

namespace rt::ch11 {

using ch03::CameraSpec;

struct PathMaterial {
  Vec3f albedo;   // the fraction of light reflected (Lambertian), per channel, in [0, 1)
  Vec3f emission; // radiance emitted from the front face (corners counter-clockwise); or 0
};

// The brightest light a scene may hold: an emission (Ke), a sky radiance or a sun irradiance.
// Far beyond any real scene's (a sun-lit white wall is about 1e4 cd/m^2 in photometric units,
// 1 here), and far below what float's sums of a million samples of a light seen through the
// brightest walls (1 / (1 - k_max_albedo) = 100 bounces' worth) can hold (3.4e38).
inline constexpr double k_max_light = 1e6;
// The largest albedo a material gets: a surface that reflects all it receives makes the light
// in a closed room grow without bound (the furnace's Le / (1 - a)), and every path end only
// by Russian roulette. An MTL's Kd in (0.99, 1] is lowered to it, with a warning.
inline constexpr float k_max_albedo = 0.99f;

// What lights the scene from outside it: a constant sky seen by rays that leave the scene,
// and a sun, a directional light with no angular size (a delta light: only next-event
// estimation can find it, never a bounced ray).
struct Environment {
  Vec3f sky;            // radiance of every direction that leaves the scene
  Vec3f sun_direction;  // unit, towards the sun
  Vec3f sun_irradiance; // on a surface that faces the sun; zero: no sun
};

// [listing:light_table]
// The emitting triangles and the cumulative distribution that picks one: triangle i is
// picked with probability area_i * luminance(emission_i) / power, the share of the scene's
// emitted light it holds, and then a uniform point on it. The density of that point per unit
// area is luminance(emission_i) / power, whatever the triangle's size.
struct LightTable {
  std::vector<int> triangles; // the emitting triangles
  std::vector<float> cdf;     // cdf[k]: probability of picking one of triangles[0..k]
  double power = 0.0;         // sum of area * luminance(emission), over the emitters
};
// [/listing:light_table]

struct PathScene {
  ch04::Mesh mesh;                     // positions and triangles
  std::vector<int> material;           // per triangle, into materials
  std::vector<PathMaterial> materials; // at least one
  Environment environment{};
  LightTable lights;       // from the materials' emission: call build_light_table after changes
  std::string description; // for the report
  std::vector<std::string> warnings; // what loading let pass, a sentence each naming its file
};

// The table of the scene's emitting triangles. Throws InputError for an emission that is
// negative or not finite, and for an emitting material whose triangles add up to no area
// (a light that cannot emit anything is a broken scene, not a dark one). Zero-area triangles
// of an emitting material that has area elsewhere are left out of the table.
LightTable build_light_table(const PathScene& scene);

// An OBJ file (chapter 05's loader, which reads the file and its MTL files once) with its MTL
// materials: Kd as albedo, Ke as emission. Faces without a material, or whose MTL file is
// missing, get the default material (grey albedo 0.8, no emission); `defaulted` counts them
// when not null. The loader's warnings (a missing MTL file, an unknown `usemtl` name) go to
// `warnings`, with one more per MTL file whose Kd values in (0.99, 1] were lowered to
// k_max_albedo. Throws InputError, naming the material and its file, for a Kd or Ke that is
// not three finite numbers in the text, a Kd below 0 or above 1, and a Ke below 0 or above
// k_max_light.
PathScene load_path_scene(const std::string& path, long long* defaulted = nullptr);

// A camera that sees a model from outside: chapter 06's framing, looking down -z at the
// middle of its box, unless from there the model is seen edge-on (its triangles, projected
// along z, cover less than 1/1000 of what they cover along x or y: a flat model in a plane
// that holds the z axis). Then it looks along the axis, x or y, where they cover the most.
CameraSpec frame_from_outside(const ch04::Mesh& mesh, double fov_degrees, Extent extent);

// The course's Cornell room (assets/cornell_room.obj.gz) is read through load_path_scene; this
// is the camera that looks into it from just inside its front wall.
CameraSpec cornell_camera();

// Chapter 10's moving scene at `time` (seconds) as a path tracer's scene: the rippling torus of
// `detail` segments, four orbiting spheres and the floor, each with its own albedo, no
// emitters. Every time gives the same triangles and materials; only the vertices move.
// With a `model` (fitted by ch10::fit_moving_model): the model waving in the torus's place,
// in the torus's material.
PathScene moving_path_scene(double time, int detail, const ch04::Mesh* model = nullptr);

// The white furnace: the inside of a closed icosphere of radius 1 (20 * 4^subdivisions
// triangles, turned to face inwards) whose every face has albedo `albedo` and emission
// `emission`. Inside, the
// radiance is emission / (1 - albedo) in every direction, whatever the shape.
PathScene make_furnace(int subdivisions, float albedo, float emission);
// Its camera: at the centre, looking along -z.
CameraSpec furnace_camera();

// A disc of radius `radius` (a fan of `segments` triangles) emitting `emission`, facing down
// at height `height` above a white Lambertian square floor of albedo `albedo` and side
// `floor_size`, centred under it; nothing else. A point of the floor right below the disc
// receives E = pi * emission * radius^2 / (radius^2 + height^2), so its radiance is
// albedo / pi * E (for a polygon of many segments, to within the polygon's area deficit).
PathScene make_disc_over_floor(float radius, float height, float emission, float albedo,
                               float floor_size, int segments);

// Every position multiplied by `scale` (its camera with scaled_camera).
void scale_scene(PathScene& scene, double scale);
CameraSpec scaled_camera(CameraSpec camera, double scale);

} // namespace rt::ch11
