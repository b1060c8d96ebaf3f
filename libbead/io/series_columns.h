// Named columns of any CSV with a header row, or vector variables of a
// MATLAB .mat file (time, input, output), for the commands that take
// measured data from anywhere (identify, explain). Rows
// with an empty or non-numeric field in them are skipped as gaps, and
// counted; time must increase. The input may come from a file and clock of
// its own (a power source's log beside a camera's): it is then held at
// each output time (its last sample at or before it), as such a state is.
#pragma once

#include <string>
#include <vector>

namespace bead {

struct Series {
  std::vector<double> t, u, y;
  int skipped = 0;
  std::string first_skip;  // where and why the first skipped row was skipped
  std::string note;        // how the input was joined, when it came from its own file
  std::string file_note;   // what a .mat file holds that no reader can use ("PATH: skipped ..."; empty: nothing)
};

struct SeriesSpec {
  std::string path, time, input, output;
  std::string input_path, input_time;  // the input's own file and time column (empty: in `path`)
};

// Without a time column, rows are unit-spaced. Throws bead::Error naming
// the file and line.
Series ReadColumns(const std::string& path, const std::string& time, const std::string& input,
                   const std::string& output);
Series ReadSeries(const SeriesSpec& spec);

// Other columns (or .mat variables) of `path` on its own clock (`time`;
// empty: the row number), for explain's recorded channels: the rows where
// every one of them is a finite number.
struct ChannelColumns {
  std::vector<double> t;
  std::vector<std::vector<double>> values;  // one per name
  std::string file_note;                    // as Series::file_note
};
ChannelColumns ReadChannelColumns(const std::string& path, const std::string& time,
                                  const std::vector<std::string>& names);

// Several inputs and the output, columns (or .mat variables) of `path` on
// its own clock: the rows where all of them are numbers.
struct MultiSeries {
  Series s;                            // t, the first input, y (for the stretches)
  std::vector<std::vector<double>> u;  // every input
};
MultiSeries ReadMultiSeries(const std::string& path, const std::string& time, const std::vector<std::string>& inputs,
                            const std::string& output);

}  // namespace bead
