// The one line a plug-in adds to make its descriptor loadable (docs/behaviour-api.md):
//   SWARMFORM_BEHAVIOUR(kMyDescriptor)
// It exports the C entry point the registry looks up with dlsym; everything else in the library may stay
// hidden. The built-in behaviours register the same Descriptor by calling Registry::add directly.
#pragma once

#include "behaviour/descriptor.hpp"

// The entry point's name, for dlsym.
#define SWARMFORM_BEHAVIOUR_ENTRY "swarmform_behaviour_descriptor"

#define SWARMFORM_BEHAVIOUR(descriptor)                                                       \
  extern "C" __attribute__((visibility("default"))) const ::swarmform::behaviour::Descriptor* \
  swarmform_behaviour_descriptor() {                                                          \
    return &(descriptor);                                                                     \
  }
