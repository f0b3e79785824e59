#pragma once
// The latest recorded episode of a run folder, as the dashboard shows it: what `srics eval`
// wrote into <run>/eval/ (or another folder given): episode-NNN.gif, episode-NNN.mp4 or a
// folder episode-NNN/ of frame-NNNNN.png, with its row of episodes.csv when there is one.

#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace srics::dashboard {

struct EpisodeMedia {
  std::string name;     // "episode-003.gif", "episode-003" (a frame folder)
  std::string path;     // relative to the run folder: "eval/episode-003.gif"
  std::string kind;     // "gif", "mp4" or "frames"
  int frames = 0;       // frame folders: frame-00000.png .. frame-<frames-1>.png
  double modified = 0;  // Unix time of the file (frame folders: of the folder)
  // the episode's row of episodes.csv beside it (column -> value), empty when missing
  std::map<std::string, std::string> metrics;
};

// The most recently written episode under <run_dir>/eval (the default of `srics eval`), or
// empty when there is none. Never throws (an unreadable folder counts as none).
std::optional<EpisodeMedia> FindLatestEpisode(const std::string& run_dir);

// Whether `relative` names a file the dashboard may serve from a run folder: only episode
// media as srics eval names them ("eval/episode-003.gif", "eval/episode-003/frame-00012.png");
// no other file, no "..", no absolute path.
bool IsEpisodeMediaPath(const std::string& relative);

}  // namespace srics::dashboard
