#include "deploy/dashboard/episode_media.h"

#include <chrono>
#include <filesystem>
#include <regex>
#include <vector>

#include "deploy/run_folder/csv.h"

namespace srics::dashboard {
namespace {

namespace fs = std::filesystem;

double UnixTime(fs::file_time_type time) {
  const auto system = std::chrono::file_clock::to_sys(time);
  return std::chrono::duration<double>(system.time_since_epoch()).count();
}

// The row of episodes.csv (or recorded.csv) whose last column, the video, is `name`.
std::map<std::string, std::string> MetricsOf(const fs::path& csv_path, const std::string& name) {
  const std::optional<run_folder::CsvTable> table = run_folder::CsvTable::Read(csv_path);
  if (!table) return {};
  for (const run_folder::CsvRow& row : table->Rows()) {
    const std::vector<std::string>& fields = row.fields();
    if (fields.size() != table->header().size() || fields.back() != name) continue;
    std::map<std::string, std::string> metrics;
    for (size_t i = 0; i < fields.size(); ++i) metrics[table->header()[i]] = fields[i];
    return metrics;
  }
  return {};
}

}  // namespace

bool IsEpisodeMediaPath(const std::string& relative) {
  static const std::regex kMedia("eval/episode-[0-9]{3,6}(\\.gif|\\.mp4|/frame-[0-9]{5}\\.png)");
  return std::regex_match(relative, kMedia);
}

std::optional<EpisodeMedia> FindLatestEpisode(const std::string& run_dir) {
  static const std::regex kName("episode-[0-9]{3,6}(\\.gif|\\.mp4)?");
  std::error_code error;
  const fs::path eval_dir = fs::path(run_dir) / "eval";
  std::optional<EpisodeMedia> latest;
  for (fs::directory_iterator it(eval_dir, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (!std::regex_match(name, kName)) continue;
    EpisodeMedia media;
    media.name = name;
    media.path = "eval/" + name;
    const fs::file_time_type time = it->last_write_time(error);
    if (error) continue;
    media.modified = UnixTime(time);
    if (it->is_directory(error)) {
      media.kind = "frames";
      char frame[32];
      while (std::snprintf(frame, sizeof frame, "frame-%05d.png", media.frames), fs::exists(it->path() / frame, error))
        ++media.frames;
      if (media.frames == 0) continue;
    } else {
      media.kind = name.substr(name.size() - 3);
    }
    // the newest; among equal times the highest number (one `srics eval` writes them in order)
    if (!latest || media.modified > latest->modified ||
        (media.modified == latest->modified && media.name > latest->name))
      latest = std::move(media);
  }
  if (latest) {
    // `srics eval` lists its episodes in episodes.csv, recording actors theirs in recorded.csv
    latest->metrics = MetricsOf(eval_dir / "episodes.csv", latest->name);
    if (latest->metrics.empty()) latest->metrics = MetricsOf(eval_dir / "recorded.csv", latest->name);
  }
  return latest;
}

}  // namespace srics::dashboard
