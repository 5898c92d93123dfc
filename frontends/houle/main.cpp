// houle: the command-line frontend. Parsing, I/O and wiring only; the work is in houle::sim and
// houle::kernel.
#include <cstdio>
#include <cstring>
#include <span>
#include <string_view>

#include "commands.hpp"
#include "houle/runtime/isa.hpp"

namespace {

constexpr const char* usage = R"(usage: houle <command> [options]

Real-time animation kernel for coastal ocean scenes.

commands:
  render [SCENE]        render an animation to images or raw frames (the built-in coast without SCENE)
  probe [SCENE] --at X,Y[,T]   where points lie, the depth, wave height, gradient and per-train amplitude,
                        wavelength, direction at points and times (--times T0:T1:DT; --json or --csv)
  map [SCENE] --grid X0:X1:DX,Y0:Y1:DY --out FILE.exr|.csv   depth, Hs and per-train amplitude, K',
                        reflected amplitude, wavelength, direction on a grid (--fields)
  bench [SCENE]         frame-time median, p90, p99, max and per-stage times over N frames
  validate SCENE        check a scene file; errors give file:line:column and what was expected
  info [SCENE]          describe a scene (the built-in coast without SCENE); warns of islands and of
                        pierheads near the domain's edge
  farm slurm|status     a frame range as a Slurm array job (or processes here), and its final check

SCENE is a TOML scene file (docs/scenes.md), or - to read it from standard input; after -- every
argument is a scene, even one whose name starts with -.

options:
  --help                this text; `houle <command> --help` for a command's options
  --version             version and the SIMD instruction set in use

environment:
  HOULE_ISA             force a kernel path: )";  // the names follow, from houle::isa_names

int version() {
  std::printf("houle %s (ISA %.*s; compiled:", HOULE_VERSION, int(houle::isa_name(houle::active_isa()).size()),
              houle::isa_name(houle::active_isa()).data());
  for (const houle::Isa isa : houle::all_isas) {
    if (houle::isa_compiled(isa)) std::printf(" %.*s", int(houle::isa_name(isa).size()), houle::isa_name(isa).data());
  }
  std::printf(")\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (const std::string_view err = houle::isa_override_error(); !err.empty()) {
    std::fprintf(stderr, "houle: %.*s\n", int(err.size()), err.data());
    return 2;
  }
  const std::string_view cmd = argc > 1 ? argv[1] : "--help";
  const std::span<char* const> rest(argv + std::min(argc, 2), argv + argc);
  if (cmd == "--help" || cmd == "-h" || cmd == "help") {
    std::printf("%s%.*s\n", usage, int(houle::isa_names.size()), houle::isa_names.data());
    return 0;
  }
  if (cmd == "--version") return version();
  if (cmd == "validate") return houle::cli::cmd_validate(rest);
  if (cmd == "info") return houle::cli::cmd_info(rest);
  if (cmd == "render") return houle::cli::cmd_render(rest);
  if (cmd == "probe") return houle::cli::cmd_probe(rest);
  if (cmd == "map") return houle::cli::cmd_map(rest);
  if (cmd == "bench") return houle::cli::cmd_bench(rest);
  if (cmd == "farm") return houle::cli::cmd_farm(rest);
  std::fprintf(stderr, "houle: unknown command '%.*s' (see houle --help)\n", int(cmd.size()), cmd.data());
  return 2;
}
