#include "frame_files.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <unistd.h>

#include "frame_writer.hpp"

namespace houle::cli {
namespace {

namespace fs = std::filesystem;

// A file's place as temp_files_in keys it: its folder as written in its path, and its name.
using Place = std::pair<std::string, std::string>;
Place place_of(const std::string& path) {
  const fs::path p(path);
  return {p.parent_path().string(), p.filename().string()};
}

// NAME.tmpDIGITS in each of `dirs`, by the place of the NAME they stand beside.
std::map<Place, std::vector<std::string>> temp_files_in(const std::set<std::string>& dirs) {
  std::map<Place, std::vector<std::string>> by_place;
  for (const std::string& dir : dirs) {
    std::error_code ec;
    for (fs::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string file = it->path().filename().string();
      const auto tmp = file.rfind(".tmp");
      if (tmp == std::string::npos || tmp + 4 == file.size() ||
          !std::all_of(file.begin() + long(tmp) + 4, file.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        continue;
      }
      by_place[{dir, file.substr(0, tmp)}].push_back(dir.empty() ? file : (fs::path(dir) / file).string());
    }
  }
  return by_place;
}

}  // namespace

std::string temp_path(const std::string& path) { return path + ".tmp" + std::to_string(::getpid()); }

SequenceOnDisk scan_sequence(const std::string& pattern, long first, long last) {
  SequenceOnDisk s;
  std::set<std::string> dirs;
  for (long n = first; n <= last; ++n) {
    const std::string name = format_frame_name(pattern, n).value();
    dirs.insert(place_of(name).first);
    if (fs::exists(name)) {
      ++s.complete;
    } else if (!s.missing.empty() && s.missing.back().second == n - 1) {
      s.missing.back().second = n;
    } else {
      s.missing.emplace_back(n, n);
    }
  }
  const auto temps = temp_files_in(dirs);
  if (temps.empty()) return s;
  for (long n = first; n <= last; ++n) {
    if (const auto it = temps.find(place_of(format_frame_name(pattern, n).value())); it != temps.end()) {
      s.temp_files.insert(s.temp_files.end(), it->second.begin(), it->second.end());
    }
  }
  return s;
}

std::vector<std::string> temp_files_of(const std::string& path) {
  const Place place = place_of(path);
  const auto temps = temp_files_in({place.first});
  const auto it = temps.find(place);
  return it == temps.end() ? std::vector<std::string>{} : it->second;
}

std::string describe_runs(const FrameRuns& runs, const char* to, const char* between, std::size_t max_runs) {
  std::string out;
  for (std::size_t i = 0; i < runs.size() && i < max_runs; ++i) {
    if (i > 0) out += between;
    out += std::to_string(runs[i].first);
    if (runs[i].second != runs[i].first) out += to + std::to_string(runs[i].second);
  }
  if (runs.size() > max_runs) out += std::string(between) + "... (" + std::to_string(runs.size() - max_runs) + " more)";
  return out;
}

long count_frames(const FrameRuns& runs) {
  long n = 0;
  for (const auto& [a, b] : runs) n += b - a + 1;
  return n;
}

}  // namespace houle::cli
