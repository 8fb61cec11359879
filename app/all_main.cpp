// predvs-all — every predvs command (runCli, app/cli.h). `predvs` runs the commands on feature
// tracks itself and hands every other command line to this executable (app/main.cpp), so that
// `predvs predict` does not load the image libraries this one links.
#include "cli.h"

#include <iostream>

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return predvs::runCli(args, std::cout, std::cerr);
}
