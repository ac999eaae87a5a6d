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
  c.id = new_clip_id();
  c.samples.resize(size_t(got));
  for (size_t i = 0; i < size_t(got); ++i) {
    float sum = 0;
    for (int ch = 0; ch < info.channels; ++ch) sum += frames[i * size_t(info.channels) + size_t(ch)];
    c.samples[i] = int16_t(std::lround(std::clamp(sum / float(info.channels), -1.0f, 1.0f) * 32767));
  }
  return c;
}

WavWriter::WavWriter(const std::string& path, int rate) : path_(path) {
  SF_INFO info{};
  info.samplerate = rate;
  info.channels = 2;
  info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
  file_ = sf_open(path.c_str(), SFM_WRITE, &info);
  if (!file_) throw AudioError(path + ": cannot write WAV file (" + sf_strerror(nullptr) + ")");
}

WavWriter::~WavWriter() {
  if (file_) sf_close(static_cast<SNDFILE*>(file_));
}

void WavWriter::write(std::span<const int16_t> stereo) {
  const sf_count_t frames = sf_count_t(stereo.size() / 2);
  if (file_ && sf_writef_short(static_cast<SNDFILE*>(file_), stereo.data(), frames) != frames)
    throw AudioError(path_ + ": short write (" + sf_strerror(static_cast<SNDFILE*>(file_)) + ")");
}

void WavWriter::close() {
  if (!file_) return;
  const int failed = sf_close(static_cast<SNDFILE*>(file_));
  file_ = nullptr;
  if (failed) throw AudioError(path_ + ": could not finish the WAV file");
}

void write_wav(const std::string& path, const std::vector<int16_t>& stereo, int rate) {
  WavWriter w(path, rate);
  w.write(stereo);
  w.close();
}

}  // namespace quantum::audio
