#include "common/progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/numbers.h"
#include "common/utf8.h"

namespace ffd {
namespace {

// The escape of an ASCII byte inside a JSON string, or "" if it stands for itself.
std::string ascii_escape(unsigned char c) {
  switch (c) {
    case 0x22: return "\\\"";  // the double quote (a number: simple source readers trip on its literal)
    case '\\': return "\\\\";
    case '\b': return "\\b";
    case '\f': return "\\f";
    case '\n': return "\\n";
    case '\r': return "\\r";
    case '\t': return "\\t";
    default: break;
  }
  if (c >= 0x20) return "";
  char buf[8];
  std::snprintf(buf, sizeof buf, "\\u%04x", c);
  return buf;
}

// "2.1 s", "42 s", "3m12s", "1h05m".
std::string duration_text(double s) {
  char buf[32];
  if (s < 10)
    std::snprintf(buf, sizeof buf, "%.1f s", s);
  else if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s / 3600), static_cast<int>(s / 60) % 60);
  return buf;
}

// Columns of the terminal behind `stream` (80 when unknown).
std::size_t terminal_columns(std::FILE* stream) {
  winsize size{};
  if (ioctl(fileno(stream), TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 80;
}

}  // namespace

const std::map<std::string, ProgressMode>& progress_mode_names() {
  static const std::map<std::string, ProgressMode> names = {
      {"auto", ProgressMode::Auto}, {"json", ProgressMode::Json}, {"none", ProgressMode::None}};
  return names;
}

ProgressMode resolve_progress_mode(ProgressMode mode, std::FILE* stream) {
  if (mode != ProgressMode::Auto) return mode;
  return isatty(fileno(stream)) ? ProgressMode::Terminal : ProgressMode::None;
}

std::string json_quote(const std::string& text) {
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      const std::string escape = ascii_escape(c);
      out += escape.empty() ? std::string(1, static_cast<char>(c)) : escape;
      ++i;
      continue;
    }
    const std::size_t length = utf8_sequence(text, i);
    out += length ? text.substr(i, length) : "\\ufffd";
    i += length ? length : 1;
  }
  return out + "\"";
}

JsonEvent::JsonEvent(const std::string& name) : line_("{\"event\":" + json_quote(name)) {}

JsonEvent& JsonEvent::raw(const std::string& key, const std::string& value) {
  line_ += "," + json_quote(key) + ":" + value;
  return *this;
}

JsonEvent& JsonEvent::text(const std::string& key, const std::string& value) { return raw(key, json_quote(value)); }

JsonEvent& JsonEvent::number(const std::string& key, double value, int decimals) {
  if (!std::isfinite(value)) return raw(key, "null");
  if (decimals >= 0) {
    const double scale = std::pow(10.0, decimals);
    value = std::round(value * scale) / scale;
  }
  return raw(key, format_number(value == 0 ? 0.0 : value));  // never "-0"
}

JsonEvent& JsonEvent::integer(const std::string& key, long long value) { return raw(key, std::to_string(value)); }

JsonEvent& JsonEvent::boolean(const std::string& key, bool value) { return raw(key, value ? "true" : "false"); }

Progress::Progress(ProgressMode mode, std::FILE* stream, double show_after_s)
    : mode_(resolve_progress_mode(mode, stream)), stream_(stream), show_after_s_(show_after_s) {
  if (mode_ == ProgressMode::Terminal) ticker_ = std::thread([this] { tick(); });
}

Progress::~Progress() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    clear();
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
}

void Progress::tick() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::milliseconds(100));
    if (!stopping_) draw();
  }
}

void Progress::write_line(const std::string& line) {
  const std::string text = line + "\n";
  std::fwrite(text.data(), 1, text.size(), stream_);
  std::fflush(stream_);
}

std::string Progress::live_text() const {
  char buf[160];
  if (in_batch_) {
    const double s = batch_clock_.ms() / 1000;
    const std::size_t processed = done_ - skipped_;
    std::snprintf(buf, sizeof buf, "%zu/%zu done, %zu failed", done_, total_, failures_);
    std::string text = buf;
    if (processed > 0 && s > 0) {
      const double rate = static_cast<double>(processed) / s;
      std::snprintf(buf, sizeof buf, ", %.3g meshes/s, ETA %s", rate,
                    duration_text(static_cast<double>(total_ - done_) / rate).c_str());
      text += buf;
    }
    return text;
  }
  const double s = step_clock_.ms() / 1000;
  if (!in_step_ || s < show_after_s_) return "";
  std::snprintf(buf, sizeof buf, "  [%zu] %s, step %zu of %zu", step_index_, step_op_.c_str(), step_index_ + 1,
                step_total_);
  std::string text = buf;
  if (fraction_ >= 0) text += ": " + std::to_string(static_cast<int>(fraction_ * 100)) + "%";
  return text + " (" + duration_text(s) + ")";
}

void Progress::draw() {
  if (mode_ != ProgressMode::Terminal) return;
  std::string text = live_text();
  const std::size_t columns = terminal_columns(stream_);
  if (text.size() >= columns) text.resize(columns - 1);  // a wrapped line cannot be rewritten
  if (text == shown_) return;
  if (text.empty()) return clear();
  std::string out = "\r" + text;
  if (shown_.size() > text.size()) out += std::string(shown_.size() - text.size(), ' ') + "\r" + text;
  std::fwrite(out.data(), 1, out.size(), stream_);
  std::fflush(stream_);
  shown_ = text;
}

void Progress::clear() {
  if (mode_ != ProgressMode::Terminal || shown_.empty()) return;
  const std::string out = "\r" + std::string(shown_.size(), ' ') + "\r";
  std::fwrite(out.data(), 1, out.size(), stream_);
  std::fflush(stream_);
  shown_.clear();
}

void Progress::step_start(std::size_t index, std::size_t total, const std::string& op) {
  std::lock_guard<std::mutex> lock(mutex_);
  in_step_ = true;
  step_index_ = index;
  step_total_ = total;
  step_op_ = op;
  fraction_ = -1;
  written_fraction_ = 0;
  step_clock_.restart();
  if (mode_ == ProgressMode::Json)
    write_line(JsonEvent("step_start").integer("index", static_cast<long long>(index))
                   .integer("total", static_cast<long long>(total)).text("op", op).str());
}

void Progress::step_progress(double fraction) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!in_step_ || !(fraction >= 0)) return;  // NaN too
  fraction = std::min(fraction, 1.0);
  if (fraction <= fraction_) return;
  fraction_ = fraction;
  if (mode_ != ProgressMode::Json) return;
  if (fraction < written_fraction_ + 0.01 && !(fraction == 1 && written_fraction_ < 1)) return;
  written_fraction_ = fraction;
  write_line(JsonEvent("step_progress").integer("index", static_cast<long long>(step_index_))
                 .number("fraction", fraction, 4).str());
}

void Progress::step_end(double ms, bool ok) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (mode_ == ProgressMode::Json)
    write_line(JsonEvent("step_end").integer("index", static_cast<long long>(step_index_)).number("ms", ms, 3)
                   .text("status", ok ? "ok" : "error").str());
  in_step_ = false;
  clear();
}

std::function<void(double)> Progress::step_callback() {
  if (mode_ == ProgressMode::None) return {};
  return [this](double fraction) { step_progress(fraction); };
}

void Progress::begin(std::size_t total) {
  std::lock_guard<std::mutex> lock(mutex_);
  in_batch_ = true;
  total_ = total;
  done_ = failures_ = skipped_ = 0;
  batch_clock_.restart();
  if (mode_ == ProgressMode::Json) write_line(JsonEvent("batch_start").integer("total", static_cast<long long>(total)).str());
  draw();
}

void Progress::item_start(const std::string& input) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (mode_ == ProgressMode::Json) write_line(JsonEvent("item_start").text("input", input).str());
}

void Progress::item_end(const std::string& input, const std::string& status, double ms, const std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  if (status == "error") ++failures_;
  if (status == "skipped") ++skipped_;
  if (mode_ == ProgressMode::Json) {
    JsonEvent e("item_end");
    e.text("input", input).text("status", status).number("ms", ms, 3);
    if (!error.empty()) e.text("error", error);
    write_line(e.str());
  }
  draw();
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (mode_ == ProgressMode::Json)
    write_line(JsonEvent("batch_end").integer("total", static_cast<long long>(total_))
                   .integer("done", static_cast<long long>(done_)).integer("failures", static_cast<long long>(failures_))
                   .number("ms", batch_clock_.ms(), 3).str());
  in_batch_ = false;
  clear();
}

void Progress::message(const std::string& line) {
  std::lock_guard<std::mutex> lock(mutex_);
  clear();
  write_line(line);
  draw();
}

void Progress::event(const JsonEvent& event) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (mode_ == ProgressMode::Json) write_line(event.str());
}

}  // namespace ffd
