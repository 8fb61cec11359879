#include "cli_args.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

/// True when `name` is one of the app's subcommands.
bool isSubcommand(CLI::App& app, const std::string& name) {
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    if (sub->get_name() == name) return true;
  return false;
}

}  // namespace

std::string oneLine(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

double parseNumberArg(const std::string& option, const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (text.empty() || end == begin || *end != '\0')
    throw std::invalid_argument(option + ": expected a number, got '" + text + "'");
  if (!std::isfinite(v) || errno == ERANGE)
    throw std::invalid_argument(option + ": expected a finite number, got '" + text + "'");
  return v;
}

long parseIntegerArg(const std::string& option, const std::string& text, long lo, long hi) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(begin, &end, 10);
  if (text.empty() || end == begin || *end != '\0' || errno == ERANGE || v < lo || v > hi)
    throw std::invalid_argument(option + ": expected an integer in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got '" + text + "'");
  return static_cast<long>(v);
}

std::vector<std::string> splitList(const std::string& option, const std::string& s) {
  if (s.empty()) throw std::invalid_argument(option + ": expected a comma-separated list, got ''");
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = s.find(',', start);
    out.push_back(s.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (out.back().empty()) throw std::invalid_argument(option + ": an empty element in '" + s + "'");
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

std::string commandLine(const std::vector<std::string>& args) {
  std::string s = "predvs";
  for (const auto& a : args) {
    const bool plain = !a.empty() && a.find_first_of(" \t\"'\\$`!*?;&|<>()") == std::string::npos;
    if (plain) {
      s += " " + a;
    } else {
      std::string q = "'";
      for (char c : a) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
      s += " " + q + "'";
    }
  }
  return s;
}

namespace {
/// `app` and the subcommands the parse went into, outermost first.
std::vector<CLI::App*> parsedChain(CLI::App& app) {
  std::vector<CLI::App*> chain{&app};
  for (;;) {
    const auto subs = chain.back()->get_subcommands();
    if (subs.empty()) return chain;
    chain.push_back(subs.front());
  }
}

/// The first "-x" / "--name[=value]" of `args` that no command of the parsed chain knows, or "".
/// CLI11 reports a missing required option before an unknown one, so `predict --inptu t.csv` said
/// "--input is required": the misspelling is the news.
std::string unknownOption(const std::vector<CLI::App*>& chain, const std::vector<std::string>& args) {
  for (const std::string& a : args) {
    if (a == "--") break;
    if (a.size() < 2 || a[0] != '-' || std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.') continue;
    const std::string name = a.substr(0, a.find('='));
    const bool known = std::any_of(chain.begin(), chain.end(), [&](CLI::App* c) {
      return c->get_option_no_throw(name) != nullptr || name == "-h" || name == "--help";
    });
    if (!known) return name;
  }
  return "";
}
}  // namespace

int parseAndRun(CLI::App& app, const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                const std::function<int()>& run) {
  try {
    if (!args.empty() && !args.front().empty() && args.front()[0] != '-' &&
        !isSubcommand(app, args.front())) {
      std::string known;
      for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        known += (known.empty() ? "" : ", ") + sub->get_name();
      throw std::invalid_argument("unknown subcommand '" + args.front() + "' (expected " + known + ")");
    }
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    app.parse(reversed);
    return run();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::RequiredError& e) {
    const std::vector<CLI::App*> chain = parsedChain(app);
    const std::string unknown = unknownOption(chain, args);
    std::string what = unknown.empty() ? oneLine(e.what()) : "unknown option '" + unknown + "'";
    // `calibrate bogus`: a word where a command's subcommand is required
    CLI::App* last = chain.back();
    const auto it = std::find(args.begin(), args.end(), last->get_name());
    const auto subs = last->get_subcommands([](CLI::App*) { return true; });
    if (unknown.empty() && !subs.empty() && it != args.end() && it + 1 != args.end() && (*(it + 1))[0] != '-') {
      std::string known;
      for (const CLI::App* s : subs) known += (known.empty() ? "" : ", ") + s->get_name();
      what = "unknown subcommand '" + *(it + 1) + "' of " + last->get_name() + " (expected " + known + ")";
    }
    err << "predvs: error: " << what << " (see predvs --help)\n";
    return 2;
  } catch (const CLI::ParseError& e) {
    err << "predvs: error: " << oneLine(e.what()) << " (see predvs --help)\n";
    return 2;
  } catch (const std::exception& e) {
    err << "predvs: error: " << oneLine(e.what()) << "\n";
    return 2;
  }
}

}  // namespace predvs
