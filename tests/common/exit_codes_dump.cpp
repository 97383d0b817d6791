// exit_codes_dump: prints the C++ exit-code constants (common/exit_codes.hpp, generated from
// common/exit_codes.json) as one JSON object {name: code}, for tests/scripts/test_exit_codes.py to compare
// with the table the Python package reads.
#include <iostream>

#include "common/exit_codes.hpp"

int main() {
  std::cout << "{";
  const char* sep = "";
  for (const auto& row : swarmform::exit_codes::kTable) {
    std::cout << sep << "\"" << row.name << "\": " << row.code;
    sep = ", ";
  }
  std::cout << "}\n";
  return swarmform::exit_codes::kExitOk;
}
