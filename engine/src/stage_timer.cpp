#include "s4d/engine/stage_timer.h"

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "s4d/engine/context.h"
#include "s4d/engine/recorder.h"
#include "s4d/engine/timestamps.h"

namespace s4d::engine {

namespace {

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

double StageTotals::stage_sum_ms() const { return std::accumulate(ms.begin(), ms.end(), other_ms); }

StageTotals& StageTotals::operator+=(const StageTotals& o) {
  if (windows > 0 && o.windows > 0 && gpu != o.gpu) throw std::logic_error("adding stage times of different clocks");
  if (o.windows > 0) gpu = o.gpu;
  for (size_t i = 0; i < o.stages.size(); ++i) {
    const auto at = std::find(stages.begin(), stages.end(), o.stages[i]);
    if (at == stages.end()) stages.push_back(o.stages[i]), ms.push_back(o.ms[i]);
    else ms[static_cast<size_t>(at - stages.begin())] += o.ms[i];
  }
  other_ms += o.other_ms, window_ms += o.window_ms, windows += o.windows;
  return *this;
}

StageTimer::StageTimer(Context& ctx, std::vector<std::string> stages, Clock clock)
    : ctx_(ctx), gpu_(clock == Clock::automatic && ctx.info().timestamps), names_(std::move(stages)),
      ms_(names_.size(), 0.0) {
  if (ctx.stage_timer() != nullptr) throw std::logic_error("a stage timer is already installed on this context");
  ctx.set_stage_timer(this);
}

StageTimer::~StageTimer() {
  try {
    ctx_.wait_idle();
  } catch (...) {  // a lost device: the pending results are gone, the pools are released below
  }
  ctx_.set_stage_timer(nullptr);
}

StageTotals StageTimer::totals() {
  ctx_.wait_idle();
  completed(UINT64_MAX);
  return {.gpu = gpu_, .stages = names_, .ms = ms_, .other_ms = other_ms_, .window_ms = window_ms_, .windows = windows_};
}

StageTimer::Window::Window(StageTimer* timer) : timer_(timer), start_(std::chrono::steady_clock::now()) {
  if (!timer_) return;
  if (timer_->open_windows_++ == 0) timer_->last_event_ = start_;
}

StageTimer::Window::~Window() {
  if (!timer_) return;
  if (!timer_->gpu_) timer_->charge_host();
  if (--timer_->open_windows_ == 0) timer_->window_ms_ += ms_since(start_), ++timer_->windows_;
}

uint32_t StageTimer::current() const {
  if (open_windows_ == 0) return kOff;
  return scopes_.empty() ? kOther : scopes_.back();
}

void StageTimer::add(uint32_t stage, double ms) {
  if (stage == kOff) return;
  (stage == kOther ? other_ms_ : ms_[stage]) += ms;
}

void StageTimer::charge_host() {
  const auto now = std::chrono::steady_clock::now();
  add(current(), std::chrono::duration<double, std::milli>(now - last_event_).count());
  last_event_ = now;
}

void StageTimer::enter(const char* stage) {
  if (!gpu_) charge_host();
  uint32_t i = 0;
  while (i < names_.size() && names_[i] != stage) ++i;
  if (i == names_.size()) names_.emplace_back(stage), ms_.push_back(0.0);
  scopes_.push_back(i);
}

void StageTimer::leave() {
  if (!gpu_) charge_host();
  scopes_.pop_back();
}

uint32_t StageTimer::take_query(Recorder& rec, StageMarks& m) {
  if (m.chunks.empty() || m.next == kChunk) {
    if (free_chunks_.empty()) {
      free_chunks_.push_back(static_cast<uint32_t>(chunks_.size()));
      chunks_.push_back(std::make_unique<TimestampQueries>(ctx_, kChunk, "stage timer queries"));
    }
    m.chunks.push_back(free_chunks_.back());
    free_chunks_.pop_back();
    m.next = 0;
    rec.reset_queries(*chunks_[m.chunks.back()]);
  }
  return m.next++;
}

void StageTimer::mark(Recorder& rec, StageMarks& m) {
  const uint32_t stage = gpu_ ? current() : kOff;
  if (stage == m.stage) return;
  const uint32_t q = take_query(rec, m);
  rec.timestamp(*chunks_[m.chunks.back()], q);
  m.marks.push_back({.chunk = m.chunks.back(), .query = q, .stage = stage});
  m.stage = stage;
}

void StageTimer::close(Recorder& rec, StageMarks& m) {
  if (m.stage == kOff) return;
  const uint32_t q = take_query(rec, m);
  rec.timestamp(*chunks_[m.chunks.back()], q);
  m.marks.push_back({.chunk = m.chunks.back(), .query = q, .stage = kOff});
  m.stage = kOff;
}

void StageTimer::submitted(StageMarks&& m, uint64_t value) {
  if (!m.chunks.empty()) pending_.push_back({value, std::move(m)});
}

void StageTimer::dropped(StageMarks&& m) {
  free_chunks_.insert(free_chunks_.end(), m.chunks.begin(), m.chunks.end());
}

void StageTimer::completed(uint64_t value) {
  size_t kept = 0;
  for (Pending& p : pending_) {
    if (p.value > value) {  // still running: keep it (a self-move would empty its marks)
      if (&pending_[kept] != &p) pending_[kept] = std::move(p);
      ++kept;
      continue;
    }
    const std::vector<StageMarks::Mark>& marks = p.marks.marks;
    std::vector<uint64_t> ticks(marks.size());
    for (size_t k = 0; k < marks.size(); ++k) ticks[k] = chunks_[marks[k].chunk]->ticks(marks[k].query);
    for (size_t k = 0; k + 1 < marks.size(); ++k) add(marks[k].stage, chunks_[0]->ticks_ms(ticks[k], ticks[k + 1]));
    dropped(std::move(p.marks));
  }
  pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(kept), pending_.end());
}

StageScope::StageScope(Context& ctx, const char* stage) : timer_(ctx.stage_timer()) {
  if (timer_) timer_->enter(stage);
}

StageScope::~StageScope() {
  if (timer_) timer_->leave();
}

}  // namespace s4d::engine
