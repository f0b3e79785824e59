#pragma once
// Internal: helpers over the Cyclone C API shared by the transport's .cc files.

#include <dds/dds.h>

#include <chrono>
#include <string>

#include "common/config/transport_config.h"
#include "common/transport/errors.h"
#include "common/transport/topics.h"

namespace srics::transport::internal {

// Throws DdsError when `ret` is negative; returns it otherwise (entity handles, counts).
inline int32_t Check(int32_t ret, const char* operation) {
  if (ret < 0) throw DdsError(operation, ret);
  return ret;
}

inline dds_duration_t ToDdsDuration(std::chrono::nanoseconds d) {
  return d.count() < 0 ? 0 : static_cast<dds_duration_t>(d.count());
}

// Deletes an entity if it is one; errors are ignored (a parent may have deleted it already).
inline void DeleteEntity(int32_t* entity) {
  if (*entity > 0) dds_delete(*entity);
  *entity = 0;
}

enum class Side { kWriter, kReader };

// The QoS of one side of a topic, from the table in topics.h and the config. Caller owns it
// (dds_delete_qos).
dds_qos_t* CreateQos(const TopicSpec& spec, Side side, const config::TransportConfig& config);

}  // namespace srics::transport::internal
