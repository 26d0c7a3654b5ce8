// The error-against-run-time report (chapter 01): every chapter executable ends with one row
// per variant it teaches, time and error side by side, printed as an aligned table and, with
// --json FILE, written as JSON for scripts and the book's plots.
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace rt {

struct ReportRow {
  std::string variant;     // e.g. "stable quadratic"
  std::string backend;     // "gpu" or "cpu"
  double ms_per_frame = 0; // median over the timed runs
  double throughput = 0;   // millions of work items (pixels, rays) per second
  std::string error;       // one-line summary of the error against the reference
  // The numbers behind `error`, by name (e.g. {"pixels_differing", 0}), for the JSON file.
  std::vector<std::pair<std::string, double>> metrics;
};

class Report {
public:
  // `unit` names the throughput column (e.g. "Mpix/s"), `reference` what errors compare to.
  Report(std::string title, std::string unit, std::string reference);

  // Context printed above the table and stored in the JSON (device, resolution, scene...).
  void add_context(std::string key, std::string value);
  void add_row(ReportRow row);

  const std::vector<ReportRow>& rows() const { return rows_; }
  void print(std::ostream& out) const;
  std::string to_json() const;
  // Throws OutputError naming the path if it cannot be written.
  void write_json(const std::string& path) const;

private:
  std::string title_;
  std::string unit_;
  std::string reference_;
  std::vector<std::pair<std::string, std::string>> context_;
  std::vector<ReportRow> rows_;
};

// Refuses, before the work, a --json path the report could never be written to: UsageError for
// an image's extension (.png, .pfm, .exr: JSON under an image's name), OutputError as
// check_output_path (rt/output_file.h) says.
void check_report_path(const std::string& path);

// Formats a count with thin grouping ("1 812") as the report prints it.
std::string group_digits(long long value);

// A number with a fixed count of decimals ("0.231"), and in scientific notation ("1.9e-07"),
// for the text of a row's error column.
std::string format_fixed(double value, int decimals);
std::string format_scientific(double value, int digits = 1);

} // namespace rt
