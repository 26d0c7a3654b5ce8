// Chapter 07: the industry's figures the benchmark compares with, read from a data file
// (book/data/anchors.json) rather than written into the code: a new measurement of another
// ray tracer, or of another GPU, is a change of data.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "protocol.h"

namespace rt::ch07 {

// One scene's figures of one system on one device, in Mrays/s (and the build in ms).
struct AnchorFigures {
  std::string scene;
  double primary = 0, ao = 0, diffuse = 0; // 0: not measured
  double build_ms = 0;
  double bytes_per_triangle = 0;
  double for_type(RayType type) const;
};

struct AnchorSet {
  std::string system; // "OptiX 9.0"
  std::string device; // as the GPU names itself: "NVIDIA H200"
  std::vector<AnchorFigures> scenes;
};

class Anchors {
public:
  Anchors() = default;
  explicit Anchors(std::vector<AnchorSet> sets) : sets_(std::move(sets)) {}

  // The set measured on `device` (a description that contains the set's device name, e.g.
  // "NVIDIA H200 (sm_90, ...)"), or null. With several, the longest device name matches.
  const AnchorSet* for_device(const std::string& device) const;
  const std::vector<AnchorSet>& sets() const { return sets_; }

private:
  std::vector<AnchorSet> sets_;
};

// The figures of a set for a scene, or null.
const AnchorFigures* find_scene(const AnchorSet* set, const std::string& scene);

// Reads the anchors file; throws InputError naming the file and the problem.
Anchors read_anchors(const std::string& path);

// The course's file (book/data/anchors.json in the source tree), or no anchors with a notice on
// `notice` when it cannot be read: a report without a share column is still a report.
Anchors course_anchors(std::ostream& notice);

} // namespace rt::ch07
