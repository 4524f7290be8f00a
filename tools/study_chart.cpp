#include "tools/study_chart.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "io/atomic_file.h"

namespace clothsim::cli {

bool gnuplot_available() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

std::string quote_text(const std::string& text) {
  std::string s = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') s += '\\';
    s += c;
  }
  return s + "\"";
}

bool render_chart(const std::string& dir, const std::string& name, int width, int height,
                  const std::string& plot_commands) {
  // One script renders both formats, to temporary names the caller's rename makes final: a failed run leaves
  // no half-written chart.
  // `reset` between the passes: a chart's settings (ranges, log scales) must not leak into the next format.
  const std::string body = "reset\nset datafile separator ','\nset datafile missing 'nan'\n" + plot_commands +
                           "\nunset output\n";
  const std::string size = std::to_string(width) + "," + std::to_string(height);
  std::string script = "# " + name + ": rendered by clothsim study; rerun with `gnuplot " + name + ".gp`\n";
  script += "set terminal pngcairo size " + size + " font 'sans,10'\nset output " + quote_text(name + ".png.tmp") +
            "\n" + body;
  script += "set terminal svg size " + size + " dynamic font 'sans,10'\nset output " +
            quote_text(name + ".svg.tmp") + "\n" + body;
  const std::filesystem::path base(dir);
  io::write_file_atomic((base / (name + ".gp")).string(), script);
  if (!gnuplot_available()) {
    std::fprintf(stderr, "clothsim study: gnuplot not found; %s.gp written, charts not rendered (tools/setup "
                         "installs gnuplot)\n", (base / name).string().c_str());
    return false;
  }
  std::string dir_arg = "'";
  for (char c : dir) dir_arg += c == '\'' ? std::string("'\\''") : std::string(1, c);
  dir_arg += "'";
  const std::string command = "cd " + dir_arg + " && gnuplot " + name + ".gp 2>" + name + ".gnuplot.log";
  if (std::system(command.c_str()) != 0)
    throw Error((base / (name + ".gp")).string(),
                "gnuplot failed (see " + name + ".gnuplot.log); expected it to write " + name + ".png and .svg");
  for (const char* ext : {".png", ".svg"}) {
    const auto final_path = base / (name + ext);
    std::filesystem::rename(base / (name + ext + ".tmp"), final_path);
  }
  std::filesystem::remove(base / (name + ".gnuplot.log"));
  return true;
}

}  // namespace clothsim::cli
