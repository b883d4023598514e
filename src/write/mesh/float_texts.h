#pragma once
// Floats as text for the text mesh formats (OBJ, ASCII PLY), remembered.
//
// The text is what std::to_chars writes: the shortest that reads back to the same float. Making
// it costs about 20 ns a float, and was half the time of writing an OBJ file. A mesh's
// coordinates take few distinct values: on a grid without rotation, one per half voxel along
// each axis, a few thousand in all, each used by thousands of vertices. So texts are kept in a
// table indexed by the float's bits; a repeated value costs a lookup and one 16-byte copy.
//
// The table holds the text of exactly the bits it is looked up with, so the output is the
// same bytes as std::to_chars whatever the values (rotated grids, normals, NaN): values that
// rarely repeat only miss, and are formatted as before.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

namespace mvox {

class FloatTexts {
  // 8192 slots (192 KiB): a 1024^3 volume's coordinates on a plain grid (about 2 x 1024 values
  // shared by x and y, and the few z values of the current layer) fit with few collisions.
  static constexpr unsigned kSlotBits = 13;

 public:
  // The longest text std::to_chars makes of a float: "-1.00000075e-36" (a sign, nine digits, a
  // point and an exponent). put() writes a whole 16-byte block, though.
  static constexpr std::size_t kLongestText = 15;
  static constexpr std::size_t kRoom = 16;  // bytes put() may write at `out`

 private:
  struct Slot {
    std::uint32_t bits = 0;
    char text[kRoom] = {};
    std::uint8_t length = 0;  // 0: empty (every float has at least one character)
  };

 public:
  // The table's memory, for memory plans.
  static constexpr std::size_t kBytes = (std::size_t{1} << kSlotBits) * sizeof(Slot);

  FloatTexts();

  // The slot a float's bits take: a multiplicative hash, whose top bits mix all of them.
  static std::size_t slot_of(std::uint32_t bits) {
    return (bits * 0x9E3779B1u) >> (32 - kSlotBits);
  }

  // Writes `value`'s text at `out` and returns its end. `out` must have kRoom bytes of room;
  // the bytes past the text are left undefined.
  char* put(char* out, float value) {
    std::uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    Slot& slot = slots_[slot_of(bits)];
    if (slot.length == 0 || slot.bits != bits) remember(slot, bits, value);
    std::memcpy(out, slot.text, kRoom);
    return out + slot.length;
  }

 private:
  static void remember(Slot& slot, std::uint32_t bits, float value);

  std::unique_ptr<Slot[]> slots_;
};

}  // namespace mvox
