// SPDX-License-Identifier: Apache-2.0
#pragma once
// A lock-free triple buffer: one writer (the physics thread) publishes whole values, one reader
// (rendering, the GUI) takes the newest whole value; neither ever waits for the other, and
// neither sees a half-written value.
//
// Three slots: the writer fills its back slot and swaps it with the middle one (marking it
// fresh); the reader, when the middle is fresh, swaps it with its front slot. The slot indices
// live packed in one atomic so each swap is a single exchange.

#include <array>
#include <atomic>
#include <cstdint>

namespace tissuesim {

template <typename T>
class TripleBuffer {
 public:
  TripleBuffer() = default;
  explicit TripleBuffer(const T& initial) { m_slots.fill(initial); }

  /// The writer's slot: fill it, then publish().
  T& back() { return m_slots[m_back]; }

  /// Makes the back slot the newest value (acquire-release: its contents are visible to the
  /// reader that takes it).
  void publish() {
    const std::uint8_t previous =
        m_middle.exchange(static_cast<std::uint8_t>(m_back | kFresh), std::memory_order_acq_rel);
    m_back = previous & kIndexMask;
  }

  /// Takes the newest published value if there is one (true), and returns the reader's slot.
  bool update() {
    if ((m_middle.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint8_t previous = m_middle.exchange(m_front, std::memory_order_acq_rel);
    m_front = previous & kIndexMask;
    return true;
  }
  const T& front() const { return m_slots[m_front]; }

 private:
  static constexpr std::uint8_t kFresh = 0x4;
  static constexpr std::uint8_t kIndexMask = 0x3;
  std::array<T, 3> m_slots{};
  std::uint8_t m_back = 0;                ///< writer only
  std::atomic<std::uint8_t> m_middle{1};  ///< shared: index | fresh flag
  std::uint8_t m_front = 2;               ///< reader only
};

}  // namespace tissuesim
