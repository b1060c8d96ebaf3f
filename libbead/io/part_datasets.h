// The datasets a part scan (format 1.1) adds to a run archive: where each
// profile stood (/profiles/layer, path_mm, frame_z_mm, frame_x_mm) and
// where the nozzle was (/log/layer, path_mm, head_speed_mm_s). Internal to
// io/: run_archive.cc reads and writes them beside the run's datasets.
#pragma once

#include <string>

#include "libbead/core/run_data.h"
#include "libbead/io/hdf5_file.h"

namespace bead {

inline constexpr const char* kKindAttribute = "kind";
inline constexpr const char* kKindPart = "part";

// A dataset's length against another's ("length mismatch: G values, but
// OTHER has W"), naming the file and the dataset: the archives' one check.
void CheckLength(std::size_t got, std::size_t want, const std::string& file, const std::string& dataset,
                 const std::string& other);

// The log's datasets that are the nozzle's motion in a part scan, never a
// recorded channel.
bool IsPartLogDataset(const std::string& name);

PartPlaces ReadPartPlaces(const h5::File& f, std::size_t profiles);
void WritePartPlaces(h5::File& f, const PartPlaces& places);
// A part scan log's nozzle datasets (`where`/layer, path_mm, and
// head_speed_mm_s when present): lengths, layers from 0, finite numbers.
void ValidatePartLog(const AcquisitionLog& log, const std::string& file, const std::string& where);
// Adds /log/layer, path_mm and head_speed_mm_s (when present) to `log`.
void ReadPartLog(const h5::File& f, AcquisitionLog& log);
void WritePartLog(h5::File& f, const AcquisitionLog& log);

}  // namespace bead
