// CLI11 validators shared by the `hedra` subcommands.
//
// CLI11's own Range calls "abc" out of range; these say what is wrong with
// the value as written, so every subcommand rejects a bad count the same way
// (exit 2, the option and the value named).
#pragma once

#include <CLI/CLI.hpp>
#include <charconv>
#include <string>
#include <system_error>

namespace hedra::tool {

// A whole number in [low, high], e.g. a --repeat count.
inline CLI::Validator whole_number_in(int low, int high, const std::string& name) {
  return CLI::Validator(
      [low, high](std::string& value) -> std::string {
        int parsed = 0;
        const char* last = value.data() + value.size();
        const std::from_chars_result result = std::from_chars(value.data(), last, parsed);
        if (result.ec != std::errc() || result.ptr != last || parsed < low || parsed > high) {
          return "expected a whole number from " + std::to_string(low) + " to " + std::to_string(high) + ", got '" +
                 value + "'";
        }
        return std::string();
      },
      std::to_string(low) + ".." + std::to_string(high), name);
}

}  // namespace hedra::tool
