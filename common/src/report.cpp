// The error-against-run-time report (chapter 01): see rt/report.h.
#include "rt/report.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <iomanip>
#include <ostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rt/error.h"
#include "rt/output_file.h"

namespace rt {

Report::Report(std::string title, std::string unit, std::string reference)
    : title_(std::move(title)), unit_(std::move(unit)), reference_(std::move(reference)) {}

void Report::add_context(std::string key, std::string value) {
  context_.emplace_back(std::move(key), std::move(value));
}

void Report::add_row(ReportRow row) { rows_.push_back(std::move(row)); }

std::string format_fixed(double value, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << value;
  return s.str();
}

std::string format_scientific(double value, int digits) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(digits) << value;
  return s.str();
}

namespace {

// Three significant figures, never scientific notation for the ranges a report shows.
std::string figure(double value) {
  if (value >= 100.0) return group_digits(static_cast<long long>(value + 0.5));
  if (value >= 10.0) return format_fixed(value, 1);
  if (value >= 1.0) return format_fixed(value, 2);
  return format_fixed(value, 3);
}

} // namespace

std::string group_digits(long long value) {
  const unsigned long long magnitude =
      value < 0 ? 0ull - static_cast<unsigned long long>(value) : value;
  const std::string digits = std::to_string(magnitude);
  std::string grouped = value < 0 ? "-" : "";
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) grouped += ' ';
    grouped += digits[i];
  }
  return grouped;
}

void Report::print(std::ostream& out) const {
  out << "\n" << title_ << "\n";
  for (const auto& [key, value] : context_) out << "  " << key << ": " << value << "\n";
  const std::vector<std::string> header = {"variant", "backend", "ms/frame", unit_,
                                           "error vs " + reference_};
  std::vector<std::vector<std::string>> cells;
  for (const ReportRow& row : rows_)
    cells.push_back({row.variant, row.backend, figure(row.ms_per_frame), figure(row.throughput),
                     row.error});
  std::vector<std::size_t> width(header.size());
  for (std::size_t c = 0; c < header.size(); ++c) {
    width[c] = header[c].size();
    for (const auto& line : cells) width[c] = std::max(width[c], line[c].size());
  }
  auto print_line = [&](const std::vector<std::string>& line) {
    for (std::size_t c = 0; c < line.size(); ++c) {
      const bool numeric = c == 2 || c == 3;
      if (c + 1 == line.size())
        out << line[c];
      else if (numeric)
        out << std::setw(static_cast<int>(width[c])) << std::right << line[c] << "  ";
      else
        out << std::setw(static_cast<int>(width[c])) << std::left << line[c] << "  ";
    }
    out << "\n";
  };
  print_line(header);
  for (const auto& line : cells) print_line(line);
  out << std::right;
}

std::string Report::to_json() const {
  nlohmann::ordered_json json;
  json["title"] = title_;
  json["throughput_unit"] = unit_;
  json["reference"] = reference_;
  json["context"] = nlohmann::ordered_json::object();
  for (const auto& [key, value] : context_) json["context"][key] = value;
  json["rows"] = nlohmann::ordered_json::array();
  for (const ReportRow& row : rows_) {
    nlohmann::ordered_json r;
    r["variant"] = row.variant;
    r["backend"] = row.backend;
    r["ms_per_frame"] = row.ms_per_frame;
    r["throughput"] = row.throughput;
    r["error"] = row.error;
    r["metrics"] = nlohmann::ordered_json::object();
    for (const auto& [name, value] : row.metrics) r["metrics"][name] = value;
    json["rows"].push_back(std::move(r));
  }
  return json.dump(2) + "\n";
}

void check_report_path(const std::string& path) {
  std::string lower = path;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* image : {".png", ".pfm", ".exr"})
    if (lower.ends_with(image))
      throw UsageError("--json '" + path + "': the report is JSON, not a " +
                       std::string(image + 1) + " image");
  check_output_path(path, "JSON report");
}

void Report::write_json(const std::string& path) const {
  const std::string text = to_json();
  write_output_file(path, "JSON report",
                    [&](std::FILE* file) { std::fwrite(text.data(), 1, text.size(), file); });
}

} // namespace rt
