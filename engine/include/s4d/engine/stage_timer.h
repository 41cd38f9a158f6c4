// Time per named stage of a repeated workload (a training step's project, sort, raster, loss, ...),
// summed over a run. Code marks its stages with StageScope; a StageTimer installed on the context
// measures them while a StageTimer::Window is open:
//   - with GPU timestamps (the compute queue has timestampValidBits > 0), every recorder writes a
//     timestamp where the stage changes between two of its commands and at its end, and the time
//     between two timestamps is charged to the stage the commands between them were recorded in;
//   - without them (or Clock::host), the host's wall clock is charged to the innermost open scope,
//     so GPU work counts where the host waits for it.
// Time inside a window but outside every scope is "other". With no timer installed, a scope costs
// one pointer test and recorders write nothing.
#pragma once
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace s4d::engine {

class Context;
class Recorder;
class TimestampQueries;

// The timestamps one recorder wrote for the context's stage timer (kept by the Recorder).
struct StageMarks {
  struct Mark {
    uint32_t chunk, query, stage;  // stage of the commands from this timestamp to the next one
  };
  std::vector<Mark> marks;
  std::vector<uint32_t> chunks;  // the timer's query pools this recorder holds
  uint32_t next = 0;             // next free query in chunks.back()
  uint32_t stage = UINT32_MAX;   // stage of the open segment; UINT32_MAX: none open
};

struct StageTotals {
  bool gpu = false;                 // GPU timestamps (else host wall clock)
  std::vector<std::string> stages;  // the names given to the timer, then any a scope added
  std::vector<double> ms;           // per stage, summed over every window
  double other_ms = 0;              // inside windows, outside every scope
  double window_ms = 0;             // host wall clock of the windows
  uint64_t windows = 0;
  double stage_sum_ms() const;      // sum of ms and other_ms
  // Adds another timer's totals, stage by stage name (the clocks must agree).
  StageTotals& operator+=(const StageTotals& other);
};

class StageTimer {
 public:
  enum class Clock { automatic, host };  // automatic: GPU timestamps where the device has them
  // Installs itself on `ctx` (one timer per context at a time: std::logic_error otherwise).
  StageTimer(Context& ctx, std::vector<std::string> stages, Clock clock = Clock::automatic);
  ~StageTimer();  // waits for the device, uninstalls
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

  bool gpu() const { return gpu_; }
  // Query pools made so far: as many as the recorders holding timestamps at once need.
  size_t query_pools() const { return chunks_.size(); }
  // Waits for every submission so far, then returns the sums.
  StageTotals totals();

  // While one is open, stages are measured; its host wall time is added to window_ms.
  class Window {
   public:
    explicit Window(StageTimer* timer);  // nullptr: measures nothing
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

   private:
    StageTimer* timer_;
    std::chrono::steady_clock::time_point start_;
  };

  // ---- Hooks for Recorder, Context and StageScope.
  void enter(const char* stage);
  void leave();
  void mark(Recorder& rec, StageMarks& m);   // before each command
  void close(Recorder& rec, StageMarks& m);  // at the end of recording
  void submitted(StageMarks&& m, uint64_t value);
  void completed(uint64_t value);  // submissions up to `value` have completed
  void dropped(StageMarks&& m);    // never submitted

  static constexpr uint32_t kOff = UINT32_MAX, kOther = UINT32_MAX - 1;

 private:
  uint32_t current() const;
  uint32_t take_query(Recorder& rec, StageMarks& m);
  void charge_host();  // host clock: the time since the last event to the current stage
  void add(uint32_t stage, double ms);

  static constexpr uint32_t kChunk = 64;  // queries per pool
  Context& ctx_;
  bool gpu_;
  std::vector<std::string> names_;
  std::vector<double> ms_;
  double other_ms_ = 0, window_ms_ = 0;
  uint64_t windows_ = 0;
  uint32_t open_windows_ = 0;
  std::vector<uint32_t> scopes_;  // open scopes, innermost last
  std::chrono::steady_clock::time_point last_event_;
  std::vector<std::unique_ptr<TimestampQueries>> chunks_;
  std::vector<uint32_t> free_chunks_;
  struct Pending {
    uint64_t value;
    StageMarks marks;
  };
  std::vector<Pending> pending_;
};

// Marks the commands recorded and the host time spent while it lives as `stage` for the context's
// stage timer, if one is installed.
class StageScope {
 public:
  StageScope(Context& ctx, const char* stage);
  ~StageScope();
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  StageTimer* timer_;
};

}  // namespace s4d::engine
