// Chapter 02: window or not. See display_choice.h.
#include "display_choice.h"

#include <iostream>

namespace rt::ch02 {

void add_display_flags(CLI::App& app, DisplayChoice& choice, const std::string& headless_help) {
  auto* headless = app.add_flag("--headless", choice.headless, headless_help);
  app.add_flag("--window", choice.window, "Open the window (an error if there is no display)")
      ->excludes(headless);
}

std::unique_ptr<Viewer> open_viewer(const DisplayChoice& choice, Extent size,
                                    const std::string& title) {
  if (choice.headless) return nullptr;
  try {
    return std::make_unique<Viewer>(size, title, true);
  } catch (const DisplayError& e) {
    if (choice.window) throw;
    std::cout << "notice: " << e.what() << "; rendering headless\n";
    return nullptr;
  }
}

} // namespace rt::ch02
