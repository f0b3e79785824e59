#pragma once
// A DDS entity held by the object that owns it: deleted when the holder goes. Needs no DDS
// header, so public headers can hold one.

#include <cstdint>
#include <utility>

namespace srics::transport {

// Owns one DDS entity handle (0: none); move-only. Deleting ignores errors: a parent may have
// deleted the entity already (deleting a participant deletes everything in it).
class OwnedEntity {
 public:
  OwnedEntity() = default;
  explicit OwnedEntity(int32_t handle) : handle_(handle) {}
  ~OwnedEntity() { Reset(); }
  OwnedEntity(OwnedEntity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  OwnedEntity& operator=(OwnedEntity&& other) noexcept {
    if (this != &other) {
      Reset();
      handle_ = std::exchange(other.handle_, 0);
    }
    return *this;
  }
  OwnedEntity(const OwnedEntity&) = delete;
  OwnedEntity& operator=(const OwnedEntity&) = delete;

  int32_t get() const { return handle_; }
  // Deletes the entity now (no-op without one).
  void Reset();

 private:
  int32_t handle_ = 0;
};

}  // namespace srics::transport
