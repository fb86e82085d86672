// Progress of long work on stderr: a live line on a terminal, NDJSON events for CI logs
// and dashboards, or nothing. One reporter serves a single run (its steps) and a batch
// (its items).
//
// Promises:
// - Terminal: one line, rewritten in place with '\r' at most ~10 times a second by a
//   ticker thread, and cleared (blanked, cursor at its start) before any other line is
//   written through message(), at step_end() and at finish() or destruction. A step is
//   shown only once it has run for `show_after_s` (1 s); a batch line from begin() on.
// - Json: one event per line, each written whole with one write, never interleaved:
//     {"event":"step_start","index":3,"total":6,"op":"remesh"}
//     {"event":"step_progress","index":3,"fraction":0.42}
//     {"event":"step_end","index":3,"ms":12.5,"status":"ok"}
//     {"event":"batch_start","total":40}
//     {"event":"item_start","input":"in/a.obj"}
//     {"event":"item_end","input":"in/a.obj","status":"ok","ms":120.5[,"error":"..."]}
//     {"event":"batch_end","total":40,"done":40,"failures":1,"ms":5230.1}
//   A step's fractions are monotone in [0, 1]; one is written each time the fraction has
//   grown by 0.01 or more since the last one written (so at most ~100 per step, and the
//   same events for the same run, times aside). Strings are escaped as RFC 8259 says;
//   bytes that are not UTF-8 become U+FFFD.
// - None: writes nothing; step_callback() is empty, so algorithms skip reporting.
// - Reporting never changes what the work computes: a callback only reads counters.
// - Thread-safe: every member may be called from any thread (one mutex). The step calls
//   describe one sequence of steps at a time; the item calls may come from many threads.
#pragma once

#include <condition_variable>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "common/timer.h"

namespace ffd {

enum class ProgressMode {
  Auto,      // Terminal if the stream is a terminal, else None
  Terminal,  // one live line
  Json,      // NDJSON events
  None,      // nothing
};

/// The CLI's names: "auto", "json", "none" (for --progress).
const std::map<std::string, ProgressMode>& progress_mode_names();

/// `mode` with Auto resolved: Terminal if `stream` is a terminal (isatty), else None.
ProgressMode resolve_progress_mode(ProgressMode mode, std::FILE* stream = stderr);

/// `text` as a JSON string literal, quotes included: '"' and '\\' escaped, control
/// characters as \n, \t, ... or \u00XX, invalid UTF-8 bytes as \uFFFD.
std::string json_quote(const std::string& text);

/// One NDJSON event built field by field, in order: {"event":NAME,KEY:VALUE,...}.
class JsonEvent {
public:
  explicit JsonEvent(const std::string& name);
  JsonEvent& text(const std::string& key, const std::string& value);
  /// A finite number in its shortest round-trip form (rounded to `decimals` places when
  /// given); null when not finite.
  JsonEvent& number(const std::string& key, double value, int decimals = -1);
  JsonEvent& integer(const std::string& key, long long value);
  JsonEvent& boolean(const std::string& key, bool value);
  /// The object's text, without a newline.
  std::string str() const { return line_ + "}"; }

private:
  JsonEvent& raw(const std::string& key, const std::string& value);
  std::string line_;
};

class Progress {
public:
  /// A reporter writing to `stream` in `mode` (Auto is resolved against `stream`).
  /// `show_after_s`: how long a step runs before a terminal shows it.
  explicit Progress(ProgressMode mode = ProgressMode::None, std::FILE* stream = stderr, double show_after_s = 1.0);
  /// Clears a terminal line (on an exception too) and stops the ticker.
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// The resolved mode: Terminal, Json or None.
  ProgressMode mode() const { return mode_; }

  // A run's steps, in order: step_start, any number of step_progress, step_end.
  /// Step `index` (0-based) of `total`, doing op `op`, starts.
  void step_start(std::size_t index, std::size_t total, const std::string& op);
  /// The current step is `fraction` done (clamped to [0, 1]; a fraction below one
  /// already reported, or NaN, is ignored, so what is shown only grows).
  void step_progress(double fraction);
  /// The current step ended after `ms`, successfully or not.
  void step_end(double ms, bool ok = true);
  /// A callback forwarding to step_progress(), for StepContext and the algorithms'
  /// progress parameters; empty in mode None, so that reporting costs nothing then.
  std::function<void(double)> step_callback();

  // A batch's items: begin, then item_start / item_end per item from any threads, finish.
  /// A batch of `total` items starts; the terminal line shows from now on.
  void begin(std::size_t total);
  /// Item `input` starts (Json only; the terminal line counts finished items).
  void item_start(const std::string& input);
  /// Item `input` finished with `status` ("ok", "error" or "skipped") after `ms`;
  /// "error" counts as a failure, "skipped" as done but not in the rate.
  void item_end(const std::string& input, const std::string& status, double ms, const std::string& error = "");
  /// The batch is over: Json writes batch_end, a terminal line is cleared.
  void finish();

  /// Writes `line` and a newline to the stream, in every mode, without tearing the
  /// live line (cleared first, redrawn after).
  void message(const std::string& line);
  /// Writes `event` in Json mode; nothing otherwise.
  void event(const JsonEvent& event);

private:
  std::string live_text() const;  // the terminal line for the current state ("" for none)
  void draw();                    // redraws the terminal line if its text changed
  void clear();                   // blanks the terminal line
  void write_line(const std::string& line);
  void tick();                    // the ticker thread

  ProgressMode mode_;
  std::FILE* stream_;
  double show_after_s_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread ticker_;
  std::string shown_;  // the terminal line as drawn
  // The current step.
  bool in_step_ = false;
  std::size_t step_index_ = 0, step_total_ = 0;
  std::string step_op_;
  double fraction_ = -1, written_fraction_ = 0;
  Stopwatch step_clock_;
  // The batch.
  bool in_batch_ = false;
  std::size_t total_ = 0, done_ = 0, failures_ = 0, skipped_ = 0;
  Stopwatch batch_clock_;
};

}  // namespace ffd
