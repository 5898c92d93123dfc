// Which frames of a sequence are on disk. A frame file is complete once it has its final name: the
// writers write under a temporary name (temp_path) and rename. A temporary file left behind is a run
// killed mid-write; the next run over those frames removes it.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace houle::cli {

/// Inclusive runs of frame numbers, in order.
using FrameRuns = std::vector<std::pair<long, long>>;

/// `path` + ".tmp" + this process's id: where a writer puts a file until it is complete.
std::string temp_path(const std::string& path);

struct SequenceOnDisk {
  long complete = 0;                    // frames whose file exists
  FrameRuns missing;                    // the others
  std::vector<std::string> temp_files;  // NAME.tmpPID beside frames of the range, of any process
};

/// Looks at frames first..last of `pattern` (a valid --out pattern: format_frame_name accepts it).
SequenceOnDisk scan_sequence(const std::string& pattern, long first, long last);
/// The temporary files (of any process) beside the single file `path`.
std::vector<std::string> temp_files_of(const std::string& path);

/// "3:5, 9" for {{3, 5}, {9, 9}} (or "3-5,9" with to = "-", between = ","); at most `max_runs` runs,
/// then ", ... (N more)".
std::string describe_runs(const FrameRuns& runs, const char* to = ":", const char* between = ", ",
                          std::size_t max_runs = 20);
long count_frames(const FrameRuns& runs);

}  // namespace houle::cli
