// predvs app — what every predvs command line shares: argument text to numbers and lists with
// errors that name the option, the one-line error, and the parse with its error handling (exit
// status 2 and one line "predvs: error: ..." for every bad argument). Used by runCli (cli.h, every
// command) and by runTrackCli (track_cli.h, the `predvs` executable's own commands).
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace predvs {

/// `s` on one line: line breaks become spaces, trailing spaces go.
std::string oneLine(std::string s);
/// A finite number from an argument; errors name the option.
double parseNumberArg(const std::string& option, const std::string& text);
/// An integer in [lo, hi] from an argument; errors name the option and the range.
long parseIntegerArg(const std::string& option, const std::string& text, long lo, long hi);
/// The elements of the comma list `s` given to `option`; throws std::invalid_argument naming the
/// option for an empty list or an empty element ("a,,b", "a,").
std::vector<std::string> splitList(const std::string& option, const std::string& s);

/// "predvs ARG ARG ..." with shell quoting where needed (recorded in summary.json).
std::string commandLine(const std::vector<std::string>& args);

/// Parses `args` (without the program name) with `app`, then returns `run()`: the exit status of
/// the subcommand parsed. An unknown first word, a CLI11 parse error or an exception from `run`
/// becomes one line "predvs: error: ..." on `err` and status 2; --help prints to `out`, status 0.
int parseAndRun(CLI::App& app, const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                const std::function<int()>& run);

}  // namespace predvs
