#include "src/cli.hpp"

#include <allanlot/version.hpp>

#include <iostream>

namespace allanlot::cli {

int run(int argc, char** argv) {
  (void)argc;
  (void)argv;
  std::cout << "allanlot " << kVersion << "\n";
  return kExitOk;
}

}  // namespace allanlot::cli
