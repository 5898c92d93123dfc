// houle farm: one frame range as independent chunks, each a `houle render --skip-existing` of its
// frames, run as the tasks of a Slurm array job or as processes on this machine, and the check that
// the whole sequence is there at the end. Everything a task does is in the sbatch script this writes,
// so --local runs the very script Slurm would.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.hpp"
#include "commands.hpp"
#include "frame_files.hpp"
#include "frame_writer.hpp"
#include "render_options.hpp"
#include "scene_source.hpp"

extern char** environ;

namespace houle::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* help = R"(usage: houle farm slurm [SCENE] --frames A:B --chunk N [options]   a Slurm array job
       houle farm status --frames A:B [--chunk N] (--out PATTERN | --raw PATH)   what is missing

Spreads frames A to B over many machines: task i of a Slurm array renders the i-th chunk of N frames
with houle render --skip-existing, so a resubmitted array renders only the frames still missing, and
a final job (houle farm status) reports what is missing and joins the chunks of a --raw target in
order. houle farm slurm --local J runs the same tasks on this machine instead.
See houle farm slurm --help and houle farm status --help.)";

constexpr const char* slurm_help = R"(usage: houle farm slurm [SCENE] --frames A:B --chunk N [--out PATTERN | --raw PATH] [render options]
                        [--sbatch "OPTIONS"] [--script PATH] [--dry-run | --submit | --local J]

Writes an sbatch script for an array job over frames A to B of SCENE (the built-in coast without one):
task i renders frames A + i*N to A + i*N + N - 1 (the last task fewer) with the render options given,
as houle render --skip-existing does: frames already complete are not rendered again, and temporary
files that a killed task left are removed. Submitting the script again, whole or some tasks of it
(sbatch --array=2,5 SCRIPT), finishes only what is missing. Run with HOULE_FARM_STEP=status, the same
script is the final check, houle farm status.

options:
  --frames A:B | N      the frames, as houle render takes them (default 0:47)
  --chunk N             frames per array task (required)
  --out PATTERN         image sequence, as houle render (default frames/%04d.png): one file per frame
  --raw PATH            raw frames to a file (not standard output): task i writes PATH.part-FIRST-LAST
                        whole, and the final check joins the parts in frame order into PATH
  render options        --size, --quality, --fps, --threads, --pixel-format, --exposure, --realtime,
                        --quiet, --verbose: handed to every task as given (houle render --help)
  --sbatch "OPTIONS"    sbatch options for the array and the check job, written as an #SBATCH line,
                        e.g. "--partition=render --time=1:00:00 --cpus-per-task=4" (with --threads 4);
                        not --array, which --frames and --chunk set
  --script PATH         the script to write (default houle-farm.sbatch); its name without extension
                        names the job and its logs, NAME-JOB_TASK.out in the working directory
  --dry-run             print the script on standard output; write and run nothing
  --submit              write the script and submit it with sbatch, then the check job to run after
                        the array ends however it ends (--dependency=afterany)
  --local J             without Slurm: write the script and run its tasks here, J at a time (logs
                        NAME-local_TASK.out), then the check; the exit code is the check's

Without --dry-run, --submit or --local, the script is written and the commands that submit it are
printed. Tasks run this houle by its absolute path, in this working directory: the machines that run
them must see both at the same place (a shared file system). Slurm allows at most MaxArraySize - 1 as
a task index (1000 by default): choose --chunk to fit.)";

constexpr const char* status_help = R"(usage: houle farm status --frames A:B [--chunk N] (--out PATTERN | --raw PATH)

Checks that frames A to B are all on disk, as a houle farm job left them. For --out, reports the
frames missing (and with --chunk, the array tasks that would render them) and the temporary files
that killed tasks left. For --raw, joins the parts PATH.part-FIRST-LAST of the chunks of N frames in
frame order into PATH (written under a temporary name, then renamed) and removes them; PATH existing
means the parts were joined.

Exit code: 0 complete, 1 frames or parts missing (or the join failed), 2 bad arguments.)";

// Read by the script: run as the final check instead of a task.
constexpr const char* step_variable = "HOULE_FARM_STEP";

// How a farm job's frames are cut, and where they go.
struct Layout {
  long first = 0, last = 0, chunk = 1;
  std::string out;                 // --out pattern, when no --raw
  std::optional<std::string> raw;  // the joined raw file
  long tasks() const { return (last - first) / chunk + 1; }
  long task_first(long i) const { return first + i * chunk; }
  long task_last(long i) const { return std::min(last, first + i * chunk + chunk - 1); }
};

std::string part_path(const std::string& raw, long first, long last) {
  return raw + ".part-" + std::to_string(first) + "-" + std::to_string(last);
}

// The array tasks whose chunks hold the given frames, as Slurm's --array takes them ("2-4,7").
std::string tasks_of(const Layout& l, const FrameRuns& frames) {
  FrameRuns tasks;
  for (const auto& [a, b] : frames) {
    const long ta = (a - l.first) / l.chunk, tb = (b - l.first) / l.chunk;
    if (!tasks.empty() && tasks.back().second >= ta - 1) tasks.back().second = std::max(tasks.back().second, tb);
    else tasks.emplace_back(ta, tb);
  }
  return describe_runs(tasks, "-", ",", tasks.size());
}

// A word the shell reads back as `s`.
std::string quote(const std::string& s) {
  const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_./:=%@+,-", c) != nullptr;
  });
  if (plain) return s;
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string quote_all(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) {
    out += ' ';
    out += quote(w);
  }
  return out;
}

// Whether sbatch options hold -a/--array.
bool sets_array(std::string_view options) {
  while (!options.empty()) {
    const auto start = options.find_first_not_of(" \t");
    if (start == std::string_view::npos) break;
    options.remove_prefix(start);
    const std::string_view word = options.substr(0, options.find_first_of(" \t"));
    if (word.starts_with("--array") || (word.starts_with("-a") && !word.starts_with("--"))) return true;
    options.remove_prefix(word.size());
  }
  return false;
}

// Fails `args` for a count outside lo..hi.
std::optional<long> take_count(Args& args, std::string_view name, long lo, long hi) {
  const auto v = args.value(name);
  if (!v) return std::nullopt;
  const auto n = parse_int(*v);
  if (!n || *n < lo || *n > hi) {
    args.fail(std::string(name) + " expects a count in " + std::to_string(lo) + ".." + std::to_string(hi) +
              ", got '" + *v + "'");
    return std::nullopt;
  }
  return long(*n);
}

// ---- houle farm status

int check_images(const Layout& l, bool with_tasks) {
  const SequenceOnDisk s = scan_sequence(l.out, l.first, l.last);
  const long total = l.last - l.first + 1;
  if (s.missing.empty()) {
    std::printf("houle farm status: frames %ld:%ld complete (%ld frames in %s)\n", l.first, l.last, total, l.out.c_str());
  } else {
    std::printf("houle farm status: %ld of %ld frames complete in %s; missing %ld: %s\n", s.complete, total,
                l.out.c_str(), total - s.complete, describe_runs(s.missing).c_str());
    if (with_tasks) {
      std::printf("houle farm status: array tasks to run again: %s (sbatch --array=%s SCRIPT; or the whole array: "
                  "complete frames are skipped)\n",
                  tasks_of(l, s.missing).c_str(), tasks_of(l, s.missing).c_str());
    }
  }
  if (!s.temp_files.empty()) {
    std::printf("houle farm status: %zu temporary files of stopped tasks (the next task over their frames removes "
                "them): %s%s\n",
                s.temp_files.size(), s.temp_files.front().c_str(), s.temp_files.size() > 1 ? " ..." : "");
  }
  return s.missing.empty() ? 0 : 1;
}

// Appends the file `from` to `to`; false (errno set) on an I/O error.
bool append_file(const std::string& from, std::FILE* to) {
  std::FILE* in = std::fopen(from.c_str(), "rb");
  if (!in) return false;
  std::vector<char> buf(1 << 20);
  bool ok = true;
  while (ok) {
    const std::size_t n = std::fread(buf.data(), 1, buf.size(), in);
    if (n > 0 && std::fwrite(buf.data(), 1, n, to) != n) ok = false;
    if (n < buf.size()) {
      ok = ok && !std::ferror(in);
      break;
    }
  }
  std::fclose(in);
  return ok;
}

int check_raw(const Layout& l) {
  const std::string& raw = *l.raw;
  if (fs::exists(raw)) {
    std::printf("houle farm status: %s complete (frames %ld:%ld, its parts joined)\n", raw.c_str(), l.first, l.last);
    return 0;
  }
  FrameRuns missing;
  for (long i = 0; i < l.tasks(); ++i) {
    if (fs::exists(part_path(raw, l.task_first(i), l.task_last(i)))) continue;
    if (!missing.empty() && missing.back().second == l.task_first(i) - 1) missing.back().second = l.task_last(i);
    else missing.emplace_back(l.task_first(i), l.task_last(i));
  }
  if (!missing.empty()) {
    std::printf("houle farm status: %s: parts missing for %ld of %ld frames: %s; array tasks to run again: %s\n",
                raw.c_str(), count_frames(missing), l.last - l.first + 1, describe_runs(missing).c_str(),
                tasks_of(l, missing).c_str());
    return 1;
  }
  const std::string tmp = temp_path(raw);
  std::FILE* out = std::fopen(tmp.c_str(), "wb");
  bool ok = out != nullptr;
  for (long i = 0; ok && i < l.tasks(); ++i) ok = append_file(part_path(raw, l.task_first(i), l.task_last(i)), out);
  if (out && std::fclose(out) != 0) ok = false;
  if (ok && std::rename(tmp.c_str(), raw.c_str()) != 0) ok = false;
  if (!ok) {
    std::fprintf(stderr, "houle farm status: %s: cannot join the parts: %s\n", raw.c_str(), std::strerror(errno));
    std::remove(tmp.c_str());
    return 1;
  }
  for (long i = 0; i < l.tasks(); ++i) std::remove(part_path(raw, l.task_first(i), l.task_last(i)).c_str());
  std::printf("houle farm status: joined %ld parts (frames %ld:%ld) into %s\n", l.tasks(), l.first, l.last, raw.c_str());
  return 0;
}

int farm_status(std::span<char* const> argv) {
  Args args("farm status", argv);
  if (args.flag("--help")) {
    std::puts(status_help);
    return 0;
  }
  Layout l;
  const auto frames = args.value("--frames");
  const auto chunk = take_count(args, "--chunk", 1, 10'000'000);
  const auto out = args.value("--out");
  l.raw = args.value("--raw");
  const std::vector<std::string> positionals = args.rest();
  if (!frames) {
    args.fail("--frames A:B is required");
  } else if (const auto f = parse_frames(*frames)) {
    l.first = f->first, l.last = f->second;
  } else {
    args.fail(std::string("--frames expects ") + frames_expected + ", got '" + *frames + "'");
  }
  if (out && l.raw) args.fail("--out and --raw exclude each other");
  if (!out && !l.raw) args.fail("--out PATTERN or --raw PATH is required");
  if (l.raw && !chunk) args.fail("--raw needs --chunk N: the parts are the chunks'");
  if (l.raw && *l.raw == "-") args.fail("--raw needs a file, not standard output");
  if (!positionals.empty()) args.fail("takes no scene, got '" + positionals[0] + "'");
  if (out) {
    if (Expected<std::string> name = format_frame_name(*out, 0); !name) args.fail("--out: " + name.error().message);
    l.out = *out;
  }
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return 2;
  }
  l.chunk = chunk.value_or(l.last - l.first + 1);
  return l.raw ? check_raw(l) : check_images(l, chunk.has_value());
}

// ---- houle farm slurm

struct Job {
  Layout layout;
  std::string name;                      // of the job and its logs: the script's stem
  std::string houle, workdir;            // absolute
  std::vector<std::string> render_args;  // SCENE and render options, as given
  std::string sbatch;                    // user's sbatch options
  std::string scene;                     // what messages call it
};

std::string status_command(const Job& j) {
  const Layout& l = j.layout;
  std::string c = "\"$houle\" farm status --frames " + std::to_string(l.first) + ":" + std::to_string(l.last) +
                  " --chunk " + std::to_string(l.chunk);
  return c + (l.raw ? " --raw " + quote(*l.raw) : " --out " + quote(l.out));
}

std::string sbatch_script(const Job& j, const std::string& script) {
  const Layout& l = j.layout;
  const std::string s = quote(script), log = j.name + "-${job%%;*}_status.out";
  std::string t = "#!/bin/bash\n";
  t += "# houle farm: frames " + std::to_string(l.first) + ":" + std::to_string(l.last) + " of " + j.scene + " in " +
       std::to_string(l.tasks()) + " array tasks of " + std::to_string(l.chunk) + " frames";
  t += l.raw ? ", joined into " + *l.raw + " at the end.\n" : ".\n";
  t += "# Written by: houle farm slurm" + quote_all(j.render_args) + " --frames " + std::to_string(l.first) + ":" +
       std::to_string(l.last) + " --chunk " + std::to_string(l.chunk) + (l.raw ? " --raw " + quote(*l.raw) : "") +
       (j.sbatch.empty() ? "" : " --sbatch " + quote(j.sbatch)) + " --script " + s + "\n";
  t += "# Each task skips the frames already complete: submitting this script again, whole or some of its\n"
       "# tasks (sbatch --array=2,5 " + s + "), finishes only what is missing.\n"
       "# houle farm slurm --submit submits it, then the final check to run after it:\n"
       "#   job=$(sbatch --parsable " + s + ")\n"
       "#   sbatch --dependency=afterany:${job%%;*} --array=0 --export=ALL," + step_variable + "=status \\\n"
       "#     --output=" + log + " " + s + "\n";
  t += "#SBATCH --job-name=" + quote(j.name) + "\n";
  t += "#SBATCH --array=0-" + std::to_string(l.tasks() - 1) + "\n";
  t += "#SBATCH --output=" + quote(j.name + "-%A_%a.out") + "\n";
  t += "#SBATCH --chdir=" + quote(j.workdir) + "\n";
  if (!j.sbatch.empty()) t += "#SBATCH " + j.sbatch + "\n";
  t += "set -eu\n";
  t += "houle=" + quote(j.houle) + "\n";
  t += std::string("if [ \"${") + step_variable + ":-}\" = status ]; then\n";
  t += "  exec " + status_command(j) + "\n";
  t += "fi\n";
  t += "task=${SLURM_ARRAY_TASK_ID:?submit with sbatch, or run with houle farm slurm --local}\n";
  t += "first=$((" + std::to_string(l.first) + " + task * " + std::to_string(l.chunk) + "))\n";
  t += "last=$((first + " + std::to_string(l.chunk - 1) + " < " + std::to_string(l.last) + " ? first + " +
       std::to_string(l.chunk - 1) + " : " + std::to_string(l.last) + "))\n";
  if (l.raw) {
    t += "if [ -e " + quote(*l.raw) + " ]; then\n";
    t += "  echo \"houle farm:\" " + quote(*l.raw) + " \"exists: the parts were joined\" >&2\n";
    t += "  exit 0\n";
    t += "fi\n";
  }
  t += "exec \"$houle\" render" + quote_all(j.render_args) + " --frames \"$first:$last\" --skip-existing";
  t += l.raw ? " --raw " + quote(*l.raw) + "\".part-$first-$last\"\n" : "\n";
  return t;
}

// The first line that `command` prints, and its exit status (-1 if it could not run).
std::pair<std::string, int> run_for_line(const std::string& command) {
  std::FILE* p = ::popen(command.c_str(), "r");
  if (!p) return {"", -1};
  char line[256] = "";
  if (!std::fgets(line, sizeof line, p)) line[0] = '\0';
  while (std::fgetc(p) != EOF) {
  }
  const int status = ::pclose(p);
  std::string s = line;
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return {s, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string_view rest = path ? path : "";
  while (!rest.empty()) {
    const auto colon = rest.find(':');
    const std::string dir(rest.substr(0, colon));
    if (::access((fs::path(dir.empty() ? "." : dir) / program).c_str(), X_OK) == 0) return true;
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return false;
}

// sbatch --parsable ... -> the job id ("123" of "123;cluster"), or nothing after printing why.
std::optional<std::string> sbatch(const std::string& arguments) {
  const auto [line, status] = run_for_line("sbatch --parsable " + arguments);
  const std::string id = line.substr(0, line.find(';'));
  if (status != 0 || id.empty() || !std::all_of(id.begin(), id.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    std::fprintf(stderr, "houle farm slurm: sbatch --parsable %s failed (exit %d)\n", arguments.c_str(), status);
    return std::nullopt;
  }
  return id;
}

int submit(const Job& j, const std::string& script) {
  if (!on_path("sbatch")) {
    std::fprintf(stderr, "houle farm slurm: sbatch is not on PATH: submit from a Slurm login node, or run the tasks "
                         "here with --local J\n");
    return 1;
  }
  const std::optional<std::string> array = sbatch(quote(script));
  if (!array) return 1;
  std::printf("houle farm: submitted array job %s: %ld tasks, logs %s-%s_TASK.out\n", array->c_str(), j.layout.tasks(),
              j.name.c_str(), array->c_str());
  const std::string log = j.name + "-" + *array + "_status.out";
  const std::optional<std::string> check =
      sbatch("--dependency=afterany:" + *array + " --array=0 --export=ALL," + step_variable + "=status --output=" +
             quote(log) + " " + quote(script));
  if (!check) return 1;
  std::printf("houle farm: submitted the final check, job %s, to run after it: %s\n", check->c_str(), log.c_str());
  return 0;
}

std::atomic<bool> stop_local{false};
extern "C" void on_stop_local(int) { stop_local = true; }

// Runs `bash script` with `variable` set in its environment, its output to `log` (or ours when empty).
pid_t spawn_script(const std::string& script, const std::string& variable, const std::string& log) {
  std::vector<std::string> env;
  const std::string name = variable.substr(0, variable.find('=') + 1);
  for (char** e = environ; *e; ++e) {
    if (std::strncmp(*e, name.c_str(), name.size()) != 0) env.emplace_back(*e);
  }
  env.push_back(variable);
  std::vector<char*> envp;
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::string bash = "bash", file = script;
  char* argv[] = {bash.data(), file.data(), nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!log.empty()) {
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  }
  pid_t pid = -1;
  if (posix_spawnp(&pid, "bash", &actions, nullptr, argv, envp.data()) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

int run_local(const Job& j, const std::string& script, long parallel) {
  const Layout& l = j.layout;
  std::signal(SIGINT, on_stop_local);
  std::signal(SIGTERM, on_stop_local);
  std::map<pid_t, long> running;
  long next = 0, failed = 0;
  bool forwarded = false;
  while (running.size() > 0 || (next < l.tasks() && !stop_local)) {
    while (!stop_local && next < l.tasks() && long(running.size()) < parallel) {
      const std::string log = j.name + "-local_" + std::to_string(next) + ".out";
      const pid_t pid = spawn_script(script, "SLURM_ARRAY_TASK_ID=" + std::to_string(next), log);
      if (pid < 0) {
        std::fprintf(stderr, "houle farm slurm: cannot start bash: %s\n", std::strerror(errno));
        stop_local = true;
        ++failed;
        break;
      }
      running[pid] = next++;
    }
    if (stop_local && !forwarded) {
      // SIGTERM reaches only us: the tasks stop after their current frame, as they would under Slurm.
      for (const auto& [pid, task] : running) ::kill(pid, SIGTERM);
      forwarded = true;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const long i = it->second;
    running.erase(it);
    const int code = exit_code(status);
    failed += code != 0;
    std::printf("houle farm: task %ld (frames %ld:%ld) %s, log %s-local_%ld.out\n", i, l.task_first(i), l.task_last(i),
                code == 0 ? "done" : ("failed with exit code " + std::to_string(code)).c_str(), j.name.c_str(), i);
    std::fflush(stdout);
  }
  if (stop_local) {
    std::fprintf(stderr, "houle farm slurm: interrupted; the same command finishes what is missing\n");
    return 130;
  }
  if (failed > 0) std::printf("houle farm: %ld of %ld tasks failed: their logs say why\n", failed, l.tasks());
  const pid_t pid = spawn_script(script, std::string(step_variable) + "=status", "");
  int status = 0;
  while (pid > 0 && ::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return pid > 0 ? exit_code(status) : 1;
}

int farm_slurm(std::span<char* const> argv) {
  Args args("farm slurm", argv);
  if (args.flag("--help")) {
    std::puts(slurm_help);
    return 0;
  }
  const auto chunk = take_count(args, "--chunk", 1, 10'000'000);
  const auto frames = args.value("--frames");
  const auto raw = args.value("--raw");
  const std::string sbatch_options = args.value("--sbatch").value_or("");
  const std::string script = args.value("--script").value_or("houle-farm.sbatch");
  const bool dry_run = args.flag("--dry-run"), submit_it = args.flag("--submit");
  const auto local = take_count(args, "--local", 1, 256);
  args.flag("--skip-existing");  // what every task does anyway
  const std::vector<std::string> given = args.unused();  // SCENE and the render options, for the tasks

  // The tasks' options, checked here as houle render checks them: an error now, not in every task.
  std::vector<std::string> checked = given;
  if (frames) checked.insert(checked.end(), {"--frames", *frames});
  if (raw) checked.insert(checked.end(), {"--raw", *raw});
  Args render_args("farm slurm", checked);
  const RenderOptions o = take_render_options(render_args);
  const std::vector<std::string> positionals = render_args.rest();
  if (render_args.failed()) args.fail(render_args.error().message.substr(std::strlen("farm slurm: ")));
  if (!chunk && !args.failed()) args.fail("--chunk N (frames per array task) is required");
  if (int(dry_run) + int(submit_it) + int(local.has_value()) > 1) args.fail("--dry-run, --submit and --local exclude each other");
  if (raw && *raw == "-") args.fail("--raw needs a file: the tasks' parts are joined into it");
  if (o.y4m) args.fail("--y4m is one stream behind one header: farm --raw frames, then convert them");
  if (!positionals.empty() && positionals[0] == "-") args.fail("the tasks read the scene themselves: give a file, not standard input");
  for (const char* a : argv) {
    if (std::strchr(a, '\n') != nullptr) args.fail("an argument holds a line break, which the script cannot carry");
  }
  if (sets_array(sbatch_options)) args.fail("--sbatch may not set --array: --frames and --chunk set it");
  if (args.failed()) {
    std::fprintf(stderr, "houle %s\n", args.error().message.c_str());
    return 2;
  }
  if (!scene_from_args(positionals, "farm slurm")) return 2;
  // The output as houle render checks it: an image sequence's folder is made by the tasks (it or the
  // nearest folder above must take it), a raw file's folder must be there.
  if (Expected<void> ok = raw ? check_raw_output(*raw) : check_image_output(o.out, o.format == PixelFormat::rgbf32); !ok) {
    std::fprintf(stderr, "houle farm slurm: %s: %s\n", ok.error().field.c_str(), ok.error().message.c_str());
    return 2;
  }

  Job j;
  j.layout = Layout{o.first, o.last, *chunk, o.out, raw};
  j.name = fs::path(script).stem().string();
  if (j.name.empty()) j.name = "houle-farm";
  std::error_code ec;
  j.houle = fs::read_symlink("/proc/self/exe", ec).string();
  j.workdir = fs::current_path(ec).string();
  if (j.houle.empty() || j.workdir.empty()) {
    std::fprintf(stderr, "houle farm slurm: cannot tell this program's path or the working directory\n");
    return 1;
  }
  j.render_args = given;
  j.sbatch = sbatch_options;
  j.scene = scene_name(positionals);
  const std::string text = sbatch_script(j, script);
  if (dry_run) {
    std::fputs(text.c_str(), stdout);
    return 0;
  }
  if (j.layout.tasks() > 1001 && !local) {
    std::fprintf(stderr, "houle farm slurm: warning: task indices up to %ld, over the 1000 that Slurm's default "
                         "MaxArraySize allows; a larger --chunk needs fewer tasks\n", j.layout.tasks() - 1);
  }
  std::ofstream(script, std::ios::trunc) << text;
  if (!fs::exists(script) || fs::file_size(script, ec) != text.size()) {
    std::fprintf(stderr, "houle farm slurm: %s: cannot write the script\n", script.c_str());
    return 1;
  }
  if (local) return run_local(j, script, *local);
  if (submit_it) return submit(j, script);
  std::printf("houle farm: wrote %s: %ld array tasks of %ld frames (frames %ld:%ld)\n", script.c_str(),
              j.layout.tasks(), j.layout.chunk, j.layout.first, j.layout.last);
  std::printf("submit it and the final check with the same command and --submit, or by hand (see its header):\n"
              "  job=$(sbatch --parsable %s)\n"
              "  sbatch --dependency=afterany:${job%%%%;*} --array=0 --export=ALL,%s=status --output=%s-${job%%%%;*}_status.out %s\n",
              quote(script).c_str(), step_variable, j.name.c_str(), quote(script).c_str());
  return 0;
}

}  // namespace

int cmd_farm(std::span<char* const> argv) {
  const std::string_view sub = argv.empty() ? "--help" : argv[0];
  if (sub == "--help" || sub == "-h" || sub == "help") {
    std::puts(help);
    return 0;
  }
  if (sub == "slurm") return farm_slurm(argv.subspan(1));
  if (sub == "status") return farm_status(argv.subspan(1));
  std::fprintf(stderr, "houle farm: unknown subcommand '%.*s' (expected slurm or status; see houle farm --help)\n",
               int(sub.size()), sub.data());
  return 2;
}

}  // namespace houle::cli
