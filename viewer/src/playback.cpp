#include "s4d/viewer/playback.h"

#include <cmath>

namespace s4d::viewer {

void Playback::advance(double seconds, double clip_seconds) {
  if (!playing) return;
  time += seconds * speed / clip_seconds;
  if (time < 1) return;
  if (loop) {
    time -= std::floor(time);
  } else {
    time = 1;
    playing = false;
  }
}

}  // namespace s4d::viewer
