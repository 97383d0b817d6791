// Bytes as lowercase hex text (two digits a byte) and back: for bytes that travel in text (the exec line
// protocol's messages, the run secret and claim tokens in the environment).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace swarmform {

std::string to_hex(std::span<const std::uint8_t> bytes);

// The value of one hex digit (either case), -1 for any other character.
int hex_digit(char c);

// `hex` as bytes; nullopt when its length is odd or a character is not a hex digit.
std::optional<std::vector<std::uint8_t>> from_hex(std::string_view hex);

}  // namespace swarmform
