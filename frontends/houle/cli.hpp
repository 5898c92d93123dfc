// Command-line parsing shared by houle's commands: options, values, and errors that say what was
// expected. Parsing never exits; commands turn a CliError into a message and exit code 2.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace houle {
enum class QualityPreset : std::uint8_t;  // houle/sim/animation.hpp
}

namespace houle::cli {

struct CliError {
  std::string message;
};

/// The arguments of one command, consumed option by option; whatever is left must be positionals.
class Args {
 public:
  Args(std::string command, std::span<char* const> argv);
  Args(std::string command, std::vector<std::string> args);

  /// True (and consumed) if the flag is present.
  bool flag(std::string_view name);
  /// The value after `name` (`--size 640x360` or `--size=640x360`), consumed; empty if absent.
  std::optional<std::string> value(std::string_view name);
  /// Every value of a repeatable option, in order.
  std::vector<std::string> values(std::string_view name);
  /// Positionals left after all options were taken; an unknown option is an error. After `--` every
  /// argument is a positional (a scene file named "-x.toml").
  std::vector<std::string> rest();
  /// Every argument not taken yet, options and positionals, in the order given.
  std::vector<std::string> unused() const;

  const std::string& command() const { return command_; }
  bool failed() const { return error_.has_value(); }
  const CliError& error() const { return *error_; }
  /// Record the first error only: later ones are usually consequences.
  void fail(std::string message);

 private:
  std::string command_;
  std::vector<std::string> args_;
  std::vector<bool> used_;
  std::size_t options_end_;  ///< the index of `--`, or the count of arguments
  std::optional<CliError> error_;
};

/// The options several commands share: `--quality Q` (draft, realtime, film) and `--threads N`
/// (1..256), stored when present; a bad value fails `args`.
void take_quality(Args& args, QualityPreset& quality);
void take_threads(Args& args, unsigned& threads);
/// The default of --threads: the machine's hardware threads (std::thread::hardware_concurrency),
/// at least 1 and at most 256. Frames do not depend on it (docs/design.md 9).
unsigned default_threads();

/// A JSON string literal of `s` (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& s);

/// --fps as the ratio file headers hold (y4m's F, EXR's framesPerSecond): 30 -> 30/1, 29.97 and
/// 30000 / 1001.0 -> 30000/1001, otherwise the nearest millionths, reduced.
std::pair<int, int> frame_rate_ratio(double fps);

std::optional<double> parse_double(std::string_view text);
std::optional<long long> parse_int(std::string_view text);
/// Image sizes houle accepts: each side at most max_image_side, at most max_image_pixels in all.
inline constexpr int max_image_side = 16384;
inline constexpr long long max_image_pixels = 1ll << 26;
inline constexpr const char* size_expected = "WxH with each in 1..16384 and at most 64 Mpixels (8192x8192)";
/// "640x360" -> {640, 360}; nothing outside the limits above.
std::optional<std::pair<int, int>> parse_size(std::string_view text);
/// "1.5,-2" or "1.5,-2,3" -> the numbers (separated by `separator`).
std::optional<std::vector<double>> parse_list(std::string_view text, char separator = ',');

}  // namespace houle::cli
