// Chapter 07: the industry's figures, read from book/data/anchors.json. See anchors.h.
#include "anchors.h"

#include <fstream>
#include <ostream>

#include <nlohmann/json.hpp>

#include "rt/error.h"

namespace rt::ch07 {

double AnchorFigures::for_type(RayType type) const {
  return type == RayType::primary ? primary : type == RayType::ao ? ao : diffuse;
}

const AnchorSet* Anchors::for_device(const std::string& device) const {
  const AnchorSet* best = nullptr;
  for (const AnchorSet& set : sets_)
    if (!set.device.empty() && device.starts_with(set.device) &&
        (best == nullptr || set.device.size() > best->device.size()))
      best = &set;
  return best;
}

const AnchorFigures* find_scene(const AnchorSet* set, const std::string& scene) {
  if (set == nullptr) return nullptr;
  for (const AnchorFigures& figures : set->scenes)
    if (figures.scene == scene) return &figures;
  return nullptr;
}

Anchors read_anchors(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the anchors file");
  try {
    const nlohmann::json file = nlohmann::json::parse(in);
    std::vector<AnchorSet> sets;
    for (const nlohmann::json& s : file.at("sets")) {
      AnchorSet set{s.at("system").get<std::string>(), s.at("device").get<std::string>(), {}};
      for (const auto& [scene, f] : s.at("scenes").items()) {
        AnchorFigures figures{scene};
        figures.primary = f.value("primary", 0.0);
        figures.ao = f.value("ao", 0.0);
        figures.diffuse = f.value("diffuse", 0.0);
        figures.build_ms = f.value("build_ms", 0.0);
        figures.bytes_per_triangle = f.value("bytes_per_triangle", 0.0);
        for (const double v : {figures.primary, figures.ao, figures.diffuse, figures.build_ms,
                               figures.bytes_per_triangle})
          if (!(v >= 0.0 && v < 1e9))
            throw InputError(path + ": " + set.system + ", " + scene +
                             ": figures must be finite and not negative");
        set.scenes.push_back(figures);
      }
      sets.push_back(std::move(set));
    }
    return Anchors(std::move(sets));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not a valid anchors file (" + e.what() + ")");
  }
}

Anchors course_anchors(std::ostream& notice) {
  try {
    return read_anchors(RT_ANCHORS_FILE);
  } catch (const Error& e) {
    notice << "note: no share column: " << e.what() << "\n";
    return {};
  }
}

} // namespace rt::ch07
