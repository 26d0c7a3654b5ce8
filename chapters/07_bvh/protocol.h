// Chapter 07: the benchmark protocol of the course as code. Every speed figure from here on
// traces these rays: one pinhole camera ray per pixel, then from each primary hit one ambient
// occlusion (ao) or diffuse ray whose direction comes from a hash of the pixel. The CPU and the
// GPU make them bit for bit alike, so their hit buffers compare exactly.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bvh.h"
#include "camera.h"
#include "cosine_sampling.h"
#include "ray.h"
#include "rt/hd.h"
#include "rt/launch.h"
#include "rt/vec.h"
#include "triangles.h"

namespace rt::ch07 {

using ch03::RayF;
using ch04::MeshHit;

// ---------------------------------------------------------------------------------------------
// The protocol's numbers (book appendix A), named once for every chapter that runs it.

inline constexpr Extent k_protocol_extent{1920, 1080}; // the image, unless --width/--height
inline constexpr int k_protocol_check_rays = 4096;     // rays of a batch traced by brute force
inline constexpr long long k_protocol_reference_rays = 1024; // ... and by the float64 reference

// ---------------------------------------------------------------------------------------------
// Views: where the camera stands for each scene of the benchmark set.

enum class ViewKind {
  auto_frame, // objects: the whole bounding box in view, seen along -z
  conference, // a corner of the conference room, looking down over the table
  sponza,     // down the long axis of the Sponza atrium
  custom,     // eye, target and field of view given by the reader
};

const char* to_string(ViewKind kind);

struct ProtocolView {
  Vec3f eye;                        // where every primary ray starts
  Vec3f target;                     // the point at the centre of the image
  float vfov_degrees = 45.0f;       // vertical field of view
  ViewKind kind = ViewKind::custom; // which rule of the protocol chose it
};

// r = 0.5 * |hi - lo|, the scale of every distance in the secondary rays. Computed in double
// from the float box and rounded once; 0 for an empty box.
float scene_radius(const Aabb& bounds);

// The whole bounding sphere of the box in view: c = centre, eye = c + (0, 0, 1) r /
// sin(vfov/2), vfov = 45. Throws InputError for an empty, flat-to-a-point or non-finite box,
// and for one so large that the eye would stand beyond ch03::k_max_coordinate.
ProtocolView auto_frame_view(const Aabb& bounds);

// The protocol's view for a scene file: a file name starting with "conference" or "sponza"
// (any case) gets that interior view, every other scene is auto-framed.
ProtocolView protocol_view(const std::string& scene_path, const Aabb& bounds);
// The interior view of a scene file (conference or sponza), if its name asks for one.
std::optional<ProtocolView> interior_view(const std::string& scene_path);

// ---------------------------------------------------------------------------------------------
// Primary rays. Chapter 03's pinhole camera already is the protocol's formula, with every
// product rounded on its own (rounded_product), so it needs no special compilation.

using PinholeCamera = ch03::PinholeCamera<float>;

inline constexpr int k_max_image_side = 16384; // pixels; W * H stays well inside an int

// The protocol camera (up = (0, 1, 0)). Throws InputError for non-finite input, eye or target
// beyond ch03::k_max_coordinate, eye and target closer than ch03::k_min_length (or equal),
// neighbouring pixels that would get the same ray (ch03::check_pixel_spacing),
// a view straight up or down (no "right" direction), a field of view outside (0, 180) degrees
// or an image side outside 1..k_max_image_side.
PinholeCamera make_protocol_camera(Vec3f eye, Vec3f target, float vfov_degrees, int width,
                                   int height);
PinholeCamera make_protocol_camera(const ProtocolView& view, int width, int height);

// [listing:camera_ray]
// Pixel (i, j), column i from the left, row j from the top:
//   sx = (2 (i + 0.5) / W - 1) tan(vfov/2) W/H,   sy = (1 - 2 (j + 0.5) / H) tan(vfov/2)
//   direction = normalize(sx right + sy up + forward), origin = eye, t in (0, inf)
RT_HD inline RayF camera_ray(const PinholeCamera& camera, int i, int j) {
  return camera.ray_through_pixel(i, j);
}
// [/listing:camera_ray]

// ---------------------------------------------------------------------------------------------
// Secondary rays.

enum class RayType { primary, ao, diffuse };

const char* to_string(RayType type);

// [listing:pcg2d]
// Jarzynski & Olano 2020, "Hash Functions for GPU Rendering": pcg2d turns a pixel's (i, j)
// into two well-mixed 32-bit words with a few multiplies, adds and shifts, no state to carry.
// Integer arithmetic wraps modulo 2^32 the same way on every machine.
RT_HD inline Vec2<std::uint32_t> pcg2d(std::uint32_t i, std::uint32_t j) {
  constexpr std::uint32_t k_multiplier = 1664525u; // Numerical Recipes' LCG constants
  constexpr std::uint32_t k_increment = 1013904223u;
  std::uint32_t x = i * k_multiplier + k_increment;
  std::uint32_t y = j * k_multiplier + k_increment;
  x += y * k_multiplier;
  y += x * k_multiplier;
  x ^= x >> 16;
  y ^= y >> 16;
  x += y * k_multiplier;
  y += x * k_multiplier;
  x ^= x >> 16;
  y ^= y >> 16;
  return {x, y};
}

// The top 24 bits of each word as a float in [0, 1): exact, since 24 bits fit the mantissa.
RT_HD inline Vec2f pcg2d_uniforms(std::uint32_t i, std::uint32_t j) {
  const Vec2<std::uint32_t> h = pcg2d(i, j);
  constexpr float k_two_to_minus_24 = 0x1p-24f;
  return {static_cast<float>(h.x >> 8) * k_two_to_minus_24,
          static_cast<float>(h.y >> 8) * k_two_to_minus_24};
}
// [/listing:pcg2d]

// The cross product as plainly written. rt::cross is more accurate (difference_of_products,
// explicit FMAs), but the protocol's normal is the textbook one, rounded as other ray tracers
// round it, so their hit buffers compare with ours.
RT_UNFUSED_HD inline Vec3f plain_cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The triangle's geometric normal, unit length, on the side the ray came from (dot with the
// ray's direction <= 0): the meshes are two-sided, and a secondary ray leaves on that side.
RT_UNFUSED_HD inline Vec3f protocol_normal(const TriangleF& tri, Vec3f ray_direction) {
  const Vec3f edge1 = tri.v1 - tri.v0, edge2 = tri.v2 - tri.v0;
  Vec3f n = plain_cross(edge1, edge2);
  float n_dot_n = dot(n, n);
  if (!(n_dot_n >= std::numeric_limits<float>::min() &&
        n_dot_n <= std::numeric_limits<float>::max())) {
    // Legs below ~1e-10 or above ~1e9 under- or overflow the cross product or its square. The
    // cross product of the edges scaled to a largest component of 1 has the same direction. If
    // that is still 0 or NaN (a segment, a point, non-finite vertices), there is no plane; the
    // normal then turns straight back along the ray, which keeps every later step finite.
    n = plain_cross(edge1 / max_component(elementwise_abs(edge1)),
                    edge2 / max_component(elementwise_abs(edge2)));
    n_dot_n = dot(n, n);
    if (!(n_dot_n > 0.0f && n_dot_n <= std::numeric_limits<float>::max()))
      return -normalize(ray_direction);
  }
  n = n / sqrtf(n_dot_n);
  return dot(n, ray_direction) > 0.0f ? -n : n;
}

// [listing:secondary_ray]
// The ao or diffuse ray of pixel (i, j) whose primary ray hit triangle `tri` at distance t:
// from the hit point, moved off the surface by 1e-4 r along the faced normal, a cosine-
// distributed direction from the pixel's hash. ao rays look for any hit within 0.1 r (the
// occlusion radius), diffuse rays for the closest hit at any distance.
RT_UNFUSED_HD inline RayF secondary_ray(RayType type, const RayF& primary, const MeshHit& hit,
                                        const TriangleF& tri, int i, int j,
                                        float scene_radius) {
  const Vec3f p = primary.origin + hit.t * primary.direction;
  const Vec3f n = protocol_normal(tri, primary.direction);
  const Vec2f u = pcg2d_uniforms(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
  RayF ray;
  ray.origin = p + n * (1e-4f * scene_radius);
  ray.direction = cosine_direction(n, u.x, u.y);
  ray.tmin = 0.0f;
  ray.tmax = type == RayType::ao ? 0.1f * scene_radius : std::numeric_limits<float>::infinity();
  return ray;
}
// [/listing:secondary_ray]

// ---------------------------------------------------------------------------------------------
// Batches, on the host. Pixel p = j * W + i (row-major, as in the hit buffer file).

// Every pixel's camera ray, row-major.
std::vector<RayF> camera_rays_cpu(const PinholeCamera& camera);

// The secondary rays of one frame: rays[k] belongs to pixel pixel[k]. Only pixels whose
// primary ray hit get one, in increasing pixel order, so every run makes the same list.
struct SecondaryRays {
  std::vector<RayF> rays;
  std::vector<int> pixel;
};

// From the primary hits of camera's W * H pixels (hit.triangle = -1: a miss). Throws rt::Error
// for RayType::primary, a hit buffer of the wrong size or a triangle id outside the mesh.
SecondaryRays secondary_rays_cpu(RayType type, const ch04::Mesh& mesh,
                                 std::span<const MeshHit> primary_hits,
                                 const PinholeCamera& camera, float scene_radius);

// The hits of a compacted batch put back at their pixels, for a hit buffer file: a pixel
// without a ray gets a miss (t = +inf, triangle = -1). Throws rt::Error if the two arrays
// differ in length or a pixel lies outside [0, pixel_count).
std::vector<MeshHit> scatter_to_pixels(std::span<const MeshHit> hits,
                                       std::span<const int> pixel, int pixel_count);

// ---------------------------------------------------------------------------------------------
// Batches on the GPU (protocol_gpu.cu): the same rays bit for bit. Pointers named d_ are device
// memory.

// Writes W * H rays to d_rays, row-major.
void camera_rays_gpu(const PinholeCamera& camera, RayF* d_rays);

// Writes the secondary rays of the hit pixels to d_rays and their pixel numbers to d_pixels
// (each of capacity W * H), in increasing pixel order as on the CPU, and returns how many. A
// hit whose triangle id lies outside the mesh counts as a miss here (never read out of bounds);
// on the CPU it is an error.
int secondary_rays_gpu(RayType type, ch04::MeshView d_mesh, const MeshHit* d_primary_hits,
                       const PinholeCamera& camera, float scene_radius, RayF* d_rays,
                       int* d_pixels);

} // namespace rt::ch07
