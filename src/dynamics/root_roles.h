// The root functions of a model, declared by their owners (docs/model.md §6):
// the cam contact declares its gap and, where its force law has one, its
// force clamp switch; the follower train declares the gap of each of its
// one-sided and contact elements. Model::root_slot() says what root r
// watches, Model::root_of() which root watches what; every consumer (the
// root functions, the simulation's and the map sensitivities' event
// handling) loops over the roots and switches on the role.
#pragma once

namespace camdyn {

/// What a root function watches (docs/model.md §6).
enum class RootRole {
  contact_gap,    ///< the cam contact's gap g [m]: onset closing, separation opening
  contact_clamp,  ///< the cam contact law's force clamp switch: the force switches on or off
  train_gap,      ///< a train element's gap −d [m]: its force switches on or off
};

/// One root function: its role, and its index within its owner (the cam
/// contact: 0, the only one; a train gap: its root among the train's).
struct RootSlot {
  RootRole role = RootRole::contact_gap;
  int index = 0;
  bool operator==(const RootSlot&) const = default;
};

}  // namespace camdyn
