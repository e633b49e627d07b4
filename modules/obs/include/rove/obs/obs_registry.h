#pragma once
/// \file
/// Registration of rove::obs's polymorphic classes (every observation and
/// action type, SensoryFrame, ActionCollection) for rove::read_object.

#include "rove/serialization/class_registry.h"

namespace rove {

/// Adds every rove::obs class to `registry` under its class name. Calling
/// it again is harmless (the same factories are re-registered). Call it
/// before read_object on data that may hold observations; SensoryFrame and
/// ActionCollection do it themselves for the global registry. Thread-safe.
void register_obs_classes(ClassRegistry& registry = ClassRegistry::global());

}  // namespace rove
