// Above layer 0, whether the two scans stand where their frames say: the
// bed does not move between layers, so its bare stretches in the rig's
// reference areas (bare in every layer, in the profile's own frame) lie
// where the layer below's scan has them. A frame height that is not the
// head's (another unit, another axis) or heights read as distances move
// them all by one step (AddedStatus::kBedMoved).
#pragma once

#include "libbead/core/rig.h"
#include "libbead/part/added_bead.h"
#include "libbead/part/surface_below.h"

namespace bead::part {

// Where the bare bed in both reference areas lies off the layer below's
// scan of it by the bead's threshold, the same way and by the same to
// within it (a frame's height moves the whole bed; material laid in an
// area is a bead there, not the same step in both): `bead` becomes a row
// not measured, kBedMoved, by how much in bed_off_mm. p: the profile's
// points in the bed frame; under: the surface below; frame_x: the
// profile frame's lateral place (the areas are in the profile's frame).
void CheckBedStayed(const StoredProfile& p, const SurfaceGrid& under, double frame_x, const Rig& rig,
                    const AddedBeadOptions& o, AddedBead& bead);

}  // namespace bead::part
