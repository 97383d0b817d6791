// A robot's three LEDs as text, as robots.csv's `leds` column holds them (docs/recording-format.md): empty
// when all three are off (black), else each as `#rrggbb` (lowercase hex), separated by one space. Empty is
// the common case (most behaviours never light them) and costs the recording one comma a row.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "common/types.hpp"

namespace swarmform {

inline constexpr std::size_t kLedTextSize = kLedCount * 8 - 1;  // "#rrggbb #rrggbb #rrggbb"

inline bool leds_off(const std::array<Rgb, kLedCount>& leds) {
  for (const Rgb& c : leds) {
    if (c != Rgb{}) return false;
  }
  return true;
}

// "#rrggbb" (lowercase): one colour, as the recording writes every colour (LEDs, world.json's floor).
inline void append_rgb_hex(std::string& out, Rgb c) {
  constexpr char kDigits[] = "0123456789abcdef";
  out.push_back('#');
  for (std::uint8_t v : {c.r, c.g, c.b}) {
    out.push_back(kDigits[v >> 4]);
    out.push_back(kDigits[v & 0xF]);
  }
}

inline void append_led_text(std::string& out, const std::array<Rgb, kLedCount>& leds) {
  if (leds_off(leds)) return;
  for (std::size_t k = 0; k < kLedCount; ++k) {
    if (k > 0) out.push_back(' ');
    append_rgb_hex(out, leds[k]);
  }
}

// 0..15 for a hex digit of either case, -1 for any other character (header-only: the viewer's reader links
// nothing of common's library).
inline int led_hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// The LEDs of `text` (append_led_text's form; hex digits in either case); nullopt when it is not that form.
inline std::optional<std::array<Rgb, kLedCount>> parse_led_text(std::string_view text) {
  std::array<Rgb, kLedCount> leds{};
  if (text.empty()) return leds;
  if (text.size() != kLedTextSize) return std::nullopt;
  for (std::size_t k = 0; k < kLedCount; ++k) {
    const std::string_view c = text.substr(k * 8, 7);
    if (c[0] != '#' || (k + 1 < kLedCount && text[k * 8 + 7] != ' ')) return std::nullopt;
    std::uint8_t v[3] = {};
    for (std::size_t i = 0; i < 3; ++i) {
      const int hi = led_hex_digit(c[1 + 2 * i]);
      const int lo = led_hex_digit(c[2 + 2 * i]);
      if (hi < 0 || lo < 0) return std::nullopt;
      v[i] = static_cast<std::uint8_t>(hi * 16 + lo);
    }
    leds[k] = {v[0], v[1], v[2]};
  }
  return leds;
}

}  // namespace swarmform
