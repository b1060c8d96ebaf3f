// The stretches of a measured series to fit or explain, and what a file's
// reading has to say, printed as identify and explain print them.
#pragma once

#include <string>
#include <vector>

#include "libbead/io/series_columns.h"
#include "libbead/series/process_on.h"

namespace bead::tools {

// The stretches of `s` to fit (the whole record with keep_off), what was
// left out printed on stdout ("PATH: left out of the fit: process off
// ..."); no stretch at all is an error naming the file (`purpose`: what
// there is then nothing to do, "fit", "explain").
ProcessOn SeriesStretches(const Series& s, const std::string& path, bool keep_off, const std::string& purpose);

// A validation run beside an input in its own file needs its own input
// file too (else it would be paired with the estimation run's input).
void CheckValidationInput(const std::string& input_file, const std::string& validate,
                          const std::string& validate_input_file);

// Prints a file's note (Series::file_note) once per distinct note.
void PrintFileNote(const std::string& note);

// The options that name a series' columns and files, as identify and
// explain take them.
struct SeriesNames {
  std::string data, time, output, input_file, input_time, validate_input_file;
  std::vector<std::string> inputs;
};

// Refuses an input on its own clock (--input-file, --input-time) beside
// several inputs, which are read from DATA on its clock; and a validation
// run whose input is not where the estimation run's is (CheckValidationInput).
void CheckInputClocks(const SeriesNames& names, const std::string& validate);

// The series of the one input from `path` (DATA, or the validation run),
// the input on its own clock when one is named (--input-time, else --time's
// name in --input-file; the validation run's in --validate-input-file);
// its file note and the rows read printed, the file named `shown` (empty:
// its path).
Series ReadOneInputSeries(const SeriesNames& names, const std::string& path, const std::string& shown = "");

}  // namespace bead::tools
