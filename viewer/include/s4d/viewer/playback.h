// The time slider's state: time t in [0, 1], play/pause, speed and looping.
#pragma once

namespace s4d::viewer {

struct Playback {
  double time = 0;     // in [0, 1]
  bool playing = false;
  double speed = 1;    // 1: t from 0 to 1 takes the clip's length in seconds
  bool loop = true;    // at t = 1 wrap to 0; otherwise stop there

  // Advances by `seconds` of wall time for a clip `clip_seconds` long (when playing).
  void advance(double seconds, double clip_seconds);
};

}  // namespace s4d::viewer
