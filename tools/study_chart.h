#pragma once
// Study output: CSV files and gnuplot charts, each written whole under a temporary name and renamed.
#include <string>

namespace clothsim::cli {

// True when a `gnuplot` executable is on the PATH.
bool gnuplot_available();

// Writes <dir>/<name>.gp, a gnuplot script that draws `plot_commands` (which read the study's CSV files by
// their names alone) into <name>.png and <name>.svg, and runs it in `dir`. Returns false, after a warning
// on stderr, when gnuplot is absent (the CSV and the script stay, to render later); throws Error when
// gnuplot fails.
bool render_chart(const std::string& dir, const std::string& name, int width, int height,
                  const std::string& plot_commands);

// A CSV field or gnuplot string, double-quoted with embedded quotes escaped.
std::string quote_text(const std::string& text);

}  // namespace clothsim::cli
