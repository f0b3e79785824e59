#include "common/transport/owned_entity.h"

#include "common/transport/dds_util.h"

namespace srics::transport {

void OwnedEntity::Reset() { internal::DeleteEntity(&handle_); }

}  // namespace srics::transport
