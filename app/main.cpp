// predvs — command-line entry point. Everything, including turning errors into the one-line
// message and exit status 2, happens in runCli() (app/cli.h) so the tests can run it in-process.
#include "cli.h"

#include <iostream>

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return predvs::runCli(args, std::cout, std::cerr);
}
