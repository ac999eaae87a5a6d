#include <sndfile.h>

#include <algorithm>
#include <cmath>

#include "audio/audio.h"

namespace quantum::audio {

Clip load_clip(const std::string& path) {
  SF_INFO info{};
  SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
  if (!f) throw AudioError(path + ": cannot read sound file (" + sf_strerror(nullptr) + ")");
  std::vector<float> frames(size_t(info.frames) * size_t(info.channels));
  const sf_count_t got = sf_readf_float(f, frames.data(), info.frames);
  sf_close(f);
  if (got <= 0) throw AudioError(path + ": no samples");
  Clip c;
  c.rate = info.samplerate;
  c.samples.resize(size_t(got));
  for (size_t i = 0; i < size_t(got); ++i) {
    float sum = 0;
    for (int ch = 0; ch < info.channels; ++ch) sum += frames[i * size_t(info.channels) + size_t(ch)];
    c.samples[i] = int16_t(std::lround(std::clamp(sum / float(info.channels), -1.0f, 1.0f) * 32767));
  }
  return c;
}

void write_wav(const std::string& path, const std::vector<int16_t>& stereo, int rate) {
  SF_INFO info{};
  info.samplerate = rate;
  info.channels = 2;
  info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  if (!f) throw AudioError(path + ": cannot write WAV file (" + sf_strerror(nullptr) + ")");
  const sf_count_t frames = sf_count_t(stereo.size() / 2);
  const sf_count_t written = sf_writef_short(f, stereo.data(), frames);
  sf_close(f);
  if (written != frames) throw AudioError(path + ": short write");
}

}  // namespace quantum::audio
