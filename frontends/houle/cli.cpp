#include "cli.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <thread>

#include "houle/sim/animation.hpp"

namespace houle::cli {

Args::Args(std::string command, std::span<char* const> argv)
    : Args(std::move(command), std::vector<std::string>(argv.begin(), argv.end())) {}

Args::Args(std::string command, std::vector<std::string> args)
    : command_(std::move(command)),
      args_(std::move(args)),
      used_(args_.size(), false),
      options_end_(std::size_t(std::find(args_.begin(), args_.end(), "--") - args_.begin())) {
  if (options_end_ < args_.size()) used_[options_end_] = true;
}

void Args::fail(std::string message) {
  if (!error_) error_ = CliError{command_ + ": " + std::move(message)};
}

bool Args::flag(std::string_view name) {
  bool found = false;
  for (std::size_t i = 0; i < options_end_; ++i) {
    if (!used_[i] && args_[i] == name) used_[i] = found = true;
  }
  return found;
}

std::vector<std::string> Args::values(std::string_view name) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < options_end_; ++i) {
    if (used_[i]) continue;
    const std::string& a = args_[i];
    if (a == name) {
      used_[i] = true;
      if (i + 1 >= options_end_) {
        fail(std::string(name) + " expects a value");
        break;
      }
      used_[i + 1] = true;
      out.push_back(args_[++i]);
    } else if (a.size() > name.size() && a.compare(0, name.size(), name) == 0 && a[name.size()] == '=') {
      used_[i] = true;
      out.push_back(a.substr(name.size() + 1));
    }
  }
  return out;
}

std::optional<std::string> Args::value(std::string_view name) {
  std::vector<std::string> v = values(name);
  if (v.size() > 1) fail(std::string(name) + " given more than once");
  if (v.empty()) return std::nullopt;
  return v.back();
}

std::vector<std::string> Args::rest() {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args_.size(); ++i) {
    if (used_[i]) continue;
    if (i < options_end_ && args_[i].size() > 1 && args_[i][0] == '-' && args_[i] != "-") {
      fail("unknown option '" + args_[i] + "' (see houle " + command_ + " --help)");
    } else {
      out.push_back(args_[i]);
    }
  }
  return out;
}

std::vector<std::string> Args::unused() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args_.size(); ++i) {
    if (!used_[i]) out.push_back(args_[i]);
  }
  return out;
}

void take_quality(Args& args, QualityPreset& quality) {
  if (auto v = args.value("--quality")) {
    const auto q = parse_quality(*v);
    if (!q) args.fail("--quality expects draft, realtime or film, got '" + *v + "'");
    else quality = *q;
  }
}

void take_threads(Args& args, unsigned& threads) {
  if (auto v = args.value("--threads")) {
    const auto n = parse_int(*v);
    if (!n || *n < 1 || *n > 256) args.fail("--threads expects a count in 1..256, got '" + *v + "'");
    else threads = unsigned(*n);
  }
}

unsigned default_threads() { return std::clamp(std::thread::hardware_concurrency(), 1u, 256u); }

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::pair<int, int> frame_rate_ratio(double fps) {
  if (std::abs(fps - std::round(fps)) < 1e-9 * fps) return {int(std::lround(fps)), 1};
  // The NTSC family (23.976, 29.97, 59.94) as broadcast defines it.
  if (const double n = fps * 1001.0 / 1000.0; n >= 0.5 && std::abs(n - std::round(n)) < 1e-4) return {int(std::lround(n)) * 1000, 1001};
  const long long num = std::max(std::llround(fps * 1e6), 1ll), g = std::gcd(num, 1000000ll);
  return {int(num / g), int(1000000ll / g)};
}

std::optional<double> parse_double(std::string_view text) {
  double v = 0.0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long long> parse_int(std::string_view text) {
  long long v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

std::optional<std::pair<int, int>> parse_size(std::string_view text) {
  const auto x = text.find('x');
  if (x == std::string_view::npos) return std::nullopt;
  const auto w = parse_int(text.substr(0, x)), h = parse_int(text.substr(x + 1));
  if (!w || !h || *w <= 0 || *h <= 0 || *w > max_image_side || *h > max_image_side || *w * *h > max_image_pixels) {
    return std::nullopt;
  }
  return std::pair<int, int>{int(*w), int(*h)};
}

std::optional<std::vector<double>> parse_list(std::string_view text, char separator) {
  std::vector<double> out;
  while (true) {
    const auto comma = text.find(separator);
    const auto v = parse_double(text.substr(0, comma));
    if (!v) return std::nullopt;
    out.push_back(*v);
    if (comma == std::string_view::npos) return out;
    text.remove_prefix(comma + 1);
  }
}

}  // namespace houle::cli
