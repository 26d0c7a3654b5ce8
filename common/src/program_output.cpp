// The end of a chapter program's run (chapter 01): see rt/program_output.h.
#include "rt/program_output.h"

#include <iostream>
#include <utility>

namespace rt {

Report start_report(std::string title, std::string unit, std::string reference,
                    Backend backend) {
  Report report(std::move(title), std::move(unit), std::move(reference));
  report.add_context("device", describe_backend(backend));
  return report;
}

std::string to_string(Extent extent) {
  return std::to_string(extent.width) + "x" + std::to_string(extent.height);
}

void write_output_image(const std::string& path, const Image& image, const std::string& note) {
  write_image(path, image);
  std::cout << "wrote " << path << (note.empty() ? "" : " (" + note + ")") << "\n";
}

void finish_report(const Report& report, const CommonOptions& options) {
  report.print(std::cout);
  if (!options.json.empty()) report.write_json(options.json);
}

} // namespace rt
