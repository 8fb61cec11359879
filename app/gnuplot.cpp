#include "gnuplot.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <sys/wait.h>

namespace predvs {
namespace {
std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}
}  // namespace

bool gnuplotAvailable() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

void requireGnuplot() {
  if (!gnuplotAvailable())
    throw std::runtime_error("gnuplot not found on PATH (install gnuplot-nox, or pass --no-plots)");
}

void runGnuplot(const std::string& dir, const std::string& script) {
  const std::string log = script + ".log";
  const std::string cmd = "cd " + shellQuote(dir) + " && gnuplot " + shellQuote(script) + " >" + shellQuote(log) + " 2>&1";
  const int status = std::system(cmd.c_str());
  const bool ok = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!ok) {
    std::ifstream in(dir + "/" + log);
    std::string first, line;
    while (std::getline(in, line))
      if (!line.empty() && line.find_first_not_of(" ^") != std::string::npos) {
        first = line;
        break;
      }
    throw std::runtime_error("gnuplot failed on " + script + (first.empty() ? "" : ": " + first));
  }
  std::remove((dir + "/" + log).c_str());
}

std::string seriesColor(size_t k) {
  static const char* kColors[] = {"#e41a1c", "#377eb8", "#4daf4a", "#984ea3", "#ff7f00", "#a65628",
                                  "#f781bf", "#17becf", "#666600", "#1a1a80", "#b3a100", "#808080"};
  return kColors[k % (sizeof(kColors) / sizeof(kColors[0]))];
}

std::string gnuplotQuote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '\\' || c == '"') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace predvs
