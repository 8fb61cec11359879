// predvs — the command-line entry point. The commands on feature tracks (predict, fit-noise,
// make-track, track-study; track_cli.h) run in this executable, which links none of ViSP's image,
// robot or detection libraries nor OpenCV's codecs. Every other command line (servo, compare,
// merge, track, calibrate, list, --help, ...) is handed unchanged to `predvs-all`, the executable
// installed beside this one, which has every command (app/all_main.cpp, cli.h).
#include "track_cli.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <vector>

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  const auto own = predvs::TrackSubcommands::names();
  if (!args.empty() && std::find(own.begin(), own.end(), args.front()) != own.end())
    return predvs::runTrackCli(args, std::cout, std::cerr);

  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string all = ((ec ? std::filesystem::path(argv[0]) : self).parent_path() / "predvs-all").string();
  ::execv(all.c_str(), argv);  // returns only when it failed
  std::cerr << "predvs: error: cannot run " << all << " (it runs every command but predict, fit-noise, make-track and "
            << "track-study): " << std::strerror(errno) << "\n";
  return 2;
}
