#pragma once
// Everything a process needs from the transport, without any DDS header:
// Participant, Writer<T>, Reader<T>, Shutdown, the envelope and the validation of samples.

#include "common/transport/endpoint.h"
#include "common/transport/errors.h"
#include "common/transport/participant.h"
#include "common/transport/shutdown.h"
#include "common/transport/topics.h"
#include "common/transport/validation.h"
#include "common/transport/wire.h"
