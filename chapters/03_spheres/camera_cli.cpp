// Chapter 03: the camera flags. See camera_cli.h.
#include "camera_cli.h"

#include <cmath>
#include <string>

#include "rt/error.h"

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
}

void validate_camera(const CameraSpec& spec) {
  if (!finite(spec.eye) || !finite(spec.target) || !finite(spec.up))
    throw UsageError("--eye, --target and --up need finite numbers");
  if (!(spec.fov_degrees > 0.0 && spec.fov_degrees < 180.0))
    throw UsageError("--fov must lie between 0 and 180 degrees (got " +
                     std::to_string(spec.fov_degrees) + ")");
  const Vec3d view = spec.target - spec.eye;
  const double view_length = length(view), up_length = length(spec.up);
  if (!(view_length > 0.0)) throw UsageError("--eye and --target are the same point");
  if (!(up_length > 0.0)) throw UsageError("--up is the zero vector");
  // Up along the view direction leaves the camera's roll undefined.
  if (length(cross(view, spec.up)) <= 1e-9 * view_length * up_length)
    throw UsageError("--up is parallel to the view direction (eye -> target)");
}

} // namespace rt::ch03
