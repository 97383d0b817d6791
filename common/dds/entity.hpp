// RAII ownership of one Cyclone entity handle (participant, domain, topic, reader, writer, waitset,
// condition): dds_delete on destruction, move-only. Deleting a parent deletes its children in Cyclone, so
// members are declared parent first and destroyed children first (reverse order), each delete a no-op on a
// stale handle.
#pragma once

#include <dds/dds.h>

#include <utility>

#include "common/dds/dds_error.hpp"

namespace swarmform::dds {

class Entity {
 public:
  Entity() = default;
  // Takes ownership of the result of a dds_create_* call, throwing DdsError if it failed.
  Entity(dds_entity_t handle, const char* call) : handle_(check(handle, call)) {}
  ~Entity() { reset(); }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, 0);
    }
    return *this;
  }

  dds_entity_t get() const { return handle_; }
  explicit operator bool() const { return handle_ > 0; }

  void reset() {
    // A parent deleted first has already deleted this child: Cyclone then says BAD_PARAMETER/ALREADY_DELETED,
    // which is harmless here, so the result is deliberately ignored.
    if (handle_ > 0) (void)dds_delete(handle_);
    handle_ = 0;
  }

 private:
  dds_entity_t handle_ = 0;
};

// A dds_qos_t owned by value.
class Qos {
 public:
  Qos() : qos_(dds_create_qos()) {}
  ~Qos() {
    if (qos_ != nullptr) dds_delete_qos(qos_);
  }
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
  Qos(Qos&& other) noexcept : qos_(std::exchange(other.qos_, nullptr)) {}
  Qos& operator=(Qos&& other) noexcept {
    std::swap(qos_, other.qos_);
    return *this;
  }
  dds_qos_t* get() const { return qos_; }

 private:
  dds_qos_t* qos_;
};

}  // namespace swarmform::dds
