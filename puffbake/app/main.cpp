#include <variant>

#include "options.h"

int main(int argc, char** argv) {
  auto parsed = puff::app::parse(argc, argv);
  if (const int* exitCode = std::get_if<int>(&parsed)) return *exitCode;
  return puff::app::run(std::get<puff::app::Options>(parsed));
}
