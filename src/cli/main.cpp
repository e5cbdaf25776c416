#include "src/cli/cli.hpp"

int main(int argc, char** argv) {
  return allanlot::cli::run(argc, argv);
}
