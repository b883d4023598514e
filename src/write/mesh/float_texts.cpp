#include "write/mesh/float_texts.h"

#include <charconv>

#include "mvox/assert.h"

namespace mvox {

FloatTexts::FloatTexts() : slots_(new Slot[std::size_t{1} << kSlotBits]) {}

void FloatTexts::remember(Slot& slot, std::uint32_t bits, float value) {
  const std::to_chars_result result = std::to_chars(slot.text, slot.text + kLongestText, value);
  // Fifteen characters hold every float (kLongestText); an error here would be a library that
  // writes longer texts, and the file would lose the value.
  MVOX_ASSERT(result.ec == std::errc());
  slot.bits = bits;
  slot.length = static_cast<std::uint8_t>(result.ptr - slot.text);
}

}  // namespace mvox
