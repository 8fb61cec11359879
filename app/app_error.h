// predvs app — how input errors are phrased.
//
// Every bad input (argument, file, cell, scenario key) becomes ONE line on stderr:
//   predvs: error: <file>:<line>: <what was expected>      (file errors)
//   predvs: error: <--option>: <what was expected>         (argument errors)
// Library code throws std::invalid_argument / std::runtime_error with that text (without the
// "predvs: error: " prefix); runCli() (cli.h) adds the prefix, flattens newlines and returns 2.
#pragma once

#include <stdexcept>
#include <string>

namespace predvs {

/// "FILE:LINE: WHAT" (LINE is 1-based; 0 means "the whole file" and is omitted).
inline std::string fileLocation(const std::string& file, int line, const std::string& what) {
  return line > 0 ? file + ":" + std::to_string(line) + ": " + what : file + ": " + what;
}

/// Throws std::invalid_argument("FILE:LINE: WHAT").
[[noreturn]] inline void throwAt(const std::string& file, int line, const std::string& what) {
  throw std::invalid_argument(fileLocation(file, line, what));
}

}  // namespace predvs
