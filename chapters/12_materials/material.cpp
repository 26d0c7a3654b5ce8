// Chapter 12: the checks every loader runs on the materials it makes. See material.h.
#include "material.h"

#include <cmath>
#include <sstream>

#include "path_scene.h"
#include "rt/error.h"

namespace rt::ch12 {

namespace {

void check_range(float value, float lo, float hi, const char* name, const std::string& where) {
  if (std::isfinite(value) && value >= lo && value <= hi) return;
  std::ostringstream text;
  text << where << ": " << name << " " << value << " is not in [" << lo << ", " << hi << "]";
  throw InputError(text.str());
}

void check_range(Vec3f value, float lo, float hi, const char* name, const std::string& where) {
  check_range(value.x, lo, hi, name, where);
  check_range(value.y, lo, hi, name, where);
  check_range(value.z, lo, hi, name, where);
}

} // namespace

void check_material(const Material& m, const std::string& where) {
  check_range(m.base_color, 0.0f, 1.0f, "base colour", where);
  check_range(m.metallic, 0.0f, 1.0f, "metallic", where);
  check_range(m.roughness, 0.0f, 1.0f, "roughness", where);
  check_range(m.transmission, 0.0f, 1.0f, "transmission", where);
  check_range(m.ior, 1.0f, 4.0f, "index of refraction", where);
  check_range(m.emission, 0.0f, float(ch11::k_max_light), "emission", where);
  if (m.model == MaterialModel::conductor) {
    check_range(m.eta, 1e-3f, 10.0f, "conductor eta", where);
    check_range(m.k, 0.0f, 20.0f, "conductor k", where);
  }
}

} // namespace rt::ch12
