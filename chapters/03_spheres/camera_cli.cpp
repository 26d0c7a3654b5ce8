// Chapter 03: the camera flags. See camera_cli.h.
#include "camera_cli.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

#include "rt/cli.h"
#include "rt/error.h"
#include "supported_range.h"

namespace rt::ch03 {
namespace {

// A vector flag written x,y,z: CLI11 splits and converts the three numbers.
void add_vector_option(CLI::App& app, const std::string& name, Vec3d& value,
                       const std::string& help) {
  app.add_option_function<std::vector<double>>(
         name,
         [&value](const std::vector<double>& v) {
           value = {v[0], v[1], v[2]};
         },
         help)
      ->delimiter(',')
      ->expected(3)
      ->type_name("X,Y,Z")
      ->default_str(std::to_string(value.x) + "," + std::to_string(value.y) + "," +
                    std::to_string(value.z));
}

bool finite(Vec3d v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool within_supported_range(Vec3d v) {
  return max_component(elementwise_abs(v)) <= k_max_coordinate;
}

// A number as the messages show it: 3 significant digits, like 1e+10 or 0.046.
std::string number_text(double x) {
  std::ostringstream text;
  text << std::setprecision(3) << x;
  return text.str();
}

std::string vector_text(Vec3d v) {
  return number_text(v.x) + "," + number_text(v.y) + "," + number_text(v.z);
}

// The sine of the smallest angle between up and the view direction (about 0.06 degrees).
constexpr double k_min_up_sine = 1e-3;
// Float steps between neighbouring pixels' rays, at least.
constexpr double k_float_steps_per_pixel = 8.0;

} // namespace

void add_camera_options(CLI::App& app, CameraSpec& spec) {
  add_vector_option(app, "--eye", spec.eye, "Camera position");
  add_vector_option(app, "--target", spec.target, "Point the camera looks at");
  add_vector_option(app, "--up", spec.up, "World up direction");
  app.add_option("--fov", spec.fov_degrees, "Vertical field of view in degrees")
      ->capture_default_str();
  app.add_option("--camera", spec.kind, "Camera kind")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, CameraKind>{{"pinhole", CameraKind::pinhole},
                                            {"orthographic", CameraKind::orthographic}},
          CLI::ignore_case))
      ->default_str("pinhole");
  add_help_paragraph(app, "Supported scales (book chapter 03): coordinates of the scene, "
                          "--eye and --target within +-" +
                              number_text(k_max_coordinate) + "; --eye and --target at least " +
                              number_text(k_min_length) +
                              " apart; neighbouring pixels' rays must differ in float (a "
                              "narrow --fov needs a small image).");
}

void validate_camera(const CameraSpec& spec) {
  if (!finite(spec.eye) || !finite(spec.target) || !finite(spec.up))
    throw UsageError("--eye, --target and --up need finite numbers");
  if (!(spec.fov_degrees > 0.0 && spec.fov_degrees < 180.0))
    throw UsageError("--fov must lie between 0 and 180 degrees (got " +
                     std::to_string(spec.fov_degrees) + ")");
  for (const auto& [flag, point] : {std::pair{"--eye", spec.eye}, {"--target", spec.target}})
    if (!within_supported_range(point))
      throw UsageError(std::string(flag) + " " + vector_text(point) +
                       " is outside the supported range: coordinates lie within +-" +
                       number_text(k_max_coordinate));
  const Vec3d view = spec.target - spec.eye;
  const double view_length = length(view), up_length = length(spec.up);
  if (!(view_length > 0.0)) throw UsageError("--eye and --target are the same point");
  // The renderer works in float: a distance that float rounds away, or one too short for the
  // squared length that normalising it forms, leaves no view direction.
  if (spec.eye.as<float>() == spec.target.as<float>())
    throw UsageError("--eye and --target are the same point in float (the renderer's "
                     "precision): move them further apart");
  if (view_length < k_min_length)
    throw UsageError("--eye and --target are " + number_text(view_length) +
                     " apart; the shortest supported distance is " + number_text(k_min_length));
  if (!(up_length > 0.0)) throw UsageError("--up is the zero vector");
  // Up along the view direction leaves the camera's roll undefined; within a thousandth of a
  // radian of it, float's rounding of the two decides the roll instead of the reader.
  if (length(cross(view, spec.up)) <= k_min_up_sine * view_length * up_length)
    throw UsageError("--up is parallel to the view direction (eye -> target), or within "
                     "0.06 degrees of it");
}

void check_pixel_spacing(const CameraSpec& spec, Extent extent) {
  if (extent.width < 1 || extent.height < 1) return; // no pixels, no rays to tell apart
  // Neighbouring pixels' screen coordinates differ by 2 tan(fov/2) / height (in x too, where
  // the aspect ratio cancels). A pinhole ray adds that step to a unit forward vector, an
  // orthographic one to the eye's coordinates; below k_float_steps_per_pixel ulps of what it
  // is added to, rays repeat or come out unevenly spaced, and the image is wrong although
  // every pixel matches a reference traced from the same rays.
  const double tan_half = std::tan(spec.fov_degrees * std::numbers::pi / 360.0);
  const double aspect = double(extent.width) / double(extent.height);
  const double ulp_of_one = std::ldexp(1.0, -23); // float's step just above 1
  if (spec.kind == CameraKind::pinhole) {
    const double step = 2.0 * tan_half / extent.height;
    const double largest = std::max(1.0, tan_half * std::max(aspect, 1.0));
    if (step < k_float_steps_per_pixel * ulp_of_one * largest) {
      const double smallest =
          2.0 * std::atan(k_float_steps_per_pixel * ulp_of_one * extent.height / 2.0) * 180.0 /
          std::numbers::pi;
      throw UsageError("--fov " + number_text(spec.fov_degrees) + " is too narrow for an " +
                       "image " + std::to_string(extent.height) +
                       " pixels high: neighbouring pixels would get the same ray in float; "
                       "the narrowest here is about " +
                       number_text(smallest) + " degrees");
    }
    return;
  }
  const double half_height = length(spec.target - spec.eye) * tan_half;
  const double step = 2.0 * half_height / extent.height;
  const double largest =
      std::max(max_component(elementwise_abs(spec.eye)), half_height * std::max(aspect, 1.0));
  if (step < k_float_steps_per_pixel * ulp_of_one * largest)
    throw UsageError("the orthographic view is " + number_text(2.0 * half_height) +
                     " high at " + number_text(largest) +
                     " from the origin: neighbouring pixels of an image " +
                     std::to_string(extent.height) +
                     " pixels high would start their rays at the same point in float");
}

} // namespace rt::ch03
