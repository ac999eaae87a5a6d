#include "listen.h"

#include <pocketsphinx.h>
#include <samplerate.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>
#include <stdexcept>

#include "audio/audio.h"
#include "output_files.h"

namespace quantum::tools {
namespace {

constexpr int kRate = 16000;  // the US English model's
const char* const kModel = "/usr/share/pocketsphinx/model/en-us";

std::string number_words(int n) {
  static const char* const ones[] = {"zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine",
                                     "ten", "eleven", "twelve", "thirteen", "fourteen", "fifteen", "sixteen",
                                     "seventeen", "eighteen", "nineteen"};
  static const char* const tens[] = {"", "", "twenty", "thirty", "forty", "fifty", "sixty", "seventy", "eighty", "ninety"};
  if (n < 20) return ones[n];
  if (n < 100) return std::string(tens[n / 10]) + (n % 10 ? std::string(" ") + ones[n % 10] : "");
  if (n < 1000) return std::string(ones[n / 100]) + " hundred" + (n % 100 ? " " + number_words(n % 100) : "");
  return number_words(n / 1000) + " thousand" + (n % 1000 ? " " + number_words(n % 1000) : "");
}

// Words as the dictionary spells them: lower case, numbers in words, punctuation gone ("Goal for
// Red! 3 to 2" -> "goal for red three to two"). espeak-ng reads the text the same way.
std::string words_of(const std::string& text) {
  std::string out, word;
  auto flush = [&] {
    while (!word.empty() && word.back() == '\'') word.pop_back();
    while (!word.empty() && word.front() == '\'') word.erase(0, 1);
    if (word.empty()) return;
    const bool digits = std::all_of(word.begin(), word.end(), [](char c) { return std::isdigit(uint8_t(c)); });
    if (!out.empty()) out += ' ';
    out += digits && word.size() < 7 ? number_words(std::atoi(word.c_str())) : word;
    word.clear();
  };
  for (char c : text) {
    if (std::isalnum(uint8_t(c)) || c == '\'') word += char(std::tolower(uint8_t(c)));
    else flush();
  }
  flush();
  return out;
}

struct Decoder {
  ps_decoder_t* ps = nullptr;
  ~Decoder() {
    if (ps) ps_free(ps);
  }
  std::string lookup(const std::string& word) const {
    char* phones = ps_lookup_word(ps, word.c_str());
    std::string s = phones ? phones : "";
    std::free(phones);
    return s;
  }
};

// espeak-ng's IPA as the recognizer's phones (ARPAbet), longest symbol first; stress and length
// marks fall away. Its own pronunciation is added to the dictionary's, so a name the dictionary
// says differently ("Clara": K L AE R AH, espeak-ng's en-us "klˈɑːɹə") is still heard.
std::string arpabet(const std::string& ipa) {
  static const std::pair<const char*, const char*> table[] = {
      {"aɪə", "AY ER"}, {"aɪ", "AY"}, {"aʊ", "AW"}, {"eɪ", "EY"}, {"oʊ", "OW"}, {"əʊ", "OW"}, {"ɔɪ", "OY"},
      {"ɪə", "IH R"}, {"eə", "EH R"}, {"ʊə", "UH R"}, {"iː", "IY"}, {"uː", "UW"}, {"ɑː", "AA"}, {"ɔː", "AO"},
      {"ɜː", "ER"}, {"tʃ", "CH"}, {"dʒ", "JH"}, {"i", "IY"}, {"ɪ", "IH"}, {"ᵻ", "IH"}, {"ɛ", "EH"}, {"e", "EH"},
      {"æ", "AE"}, {"a", "AE"}, {"ɑ", "AA"}, {"ɒ", "AA"}, {"ɔ", "AO"}, {"o", "OW"}, {"u", "UW"}, {"ʊ", "UH"},
      {"ʌ", "AH"}, {"ə", "AH"}, {"ɐ", "AH"}, {"ɚ", "ER"}, {"ɝ", "ER"}, {"ɜ", "ER"}, {"p", "P"}, {"b", "B"},
      {"t", "T"}, {"d", "D"}, {"k", "K"}, {"ɡ", "G"}, {"g", "G"}, {"f", "F"}, {"v", "V"}, {"θ", "TH"}, {"ð", "DH"},
      {"s", "S"}, {"z", "Z"}, {"ʃ", "SH"}, {"ʒ", "ZH"}, {"h", "HH"}, {"x", "HH"}, {"m", "M"}, {"n", "N"},
      {"ŋ", "NG"}, {"l", "L"}, {"ɬ", "L"}, {"ɹ", "R"}, {"r", "R"}, {"ɾ", "D"}, {"ʔ", "T"}, {"j", "Y"}, {"w", "W"},
  };
  std::string phones, last;
  for (size_t at = 0; at < ipa.size();) {
    const char* phone = nullptr;
    size_t length = 1;
    for (const auto& [symbol, arpa] : table)
      if (ipa.compare(at, std::strlen(symbol), symbol) == 0) {
        phone = arpa, length = std::strlen(symbol);
        break;
      }
    at += length;
    if (!phone || last == phone) continue;  // a mark, or a doubled phone ("ɹɹ")
    phones += (phones.empty() ? "" : " ") + std::string(phone);
    last = phone;
  }
  return phones;
}

// "goal for red" -> {"goal", "for", "red"} (words_of's words, one space apart).
std::vector<std::string> split(const std::string& words) {
  std::vector<std::string> out;
  for (size_t from = 0; from < words.size();) {
    const size_t to = std::min(words.find(' ', from), words.size());
    out.push_back(words.substr(from, to - from));
    from = to + 1;
  }
  return out;
}

// "goal for clara_2" -> "goal for clara".
std::string base_words(const std::string& hyp) {
  std::string out;
  bool variant = false;
  for (char c : hyp) {
    if (c == '_') variant = true;
    else if (c == ' ') variant = false;
    if (!variant) out += c;
  }
  return out;
}

std::vector<int16_t> mono_16k(const std::string& path) {
  audio::Clip clip;
  try {
    clip = audio::load_clip(path);
  } catch (const audio::AudioError& e) {
    throw std::runtime_error(e.what());
  }
  std::vector<float> in(clip.samples.size()), out(size_t(double(clip.samples.size()) * kRate / clip.rate) + 16);
  src_short_to_float_array(clip.samples.data(), in.data(), int(in.size()));
  SRC_DATA data{};
  data.data_in = in.data(), data.input_frames = long(in.size());
  data.data_out = out.data(), data.output_frames = long(out.size());
  data.src_ratio = double(kRate) / clip.rate;
  if (const int error = src_simple(&data, SRC_SINC_MEDIUM_QUALITY, 1))
    throw std::runtime_error(path + ": cannot resample: " + src_strerror(error));
  std::vector<int16_t> samples(size_t(data.output_frames_gen));
  src_float_to_short_array(out.data(), samples.data(), int(samples.size()));
  return samples;
}

// A match's sound runs from its start to half a second past its last frame or its last phrase,
// whichever is later (MatchAudio::finish). A WAV may be a quarter of a second short of the log's
// last moment (a phrase's end is logged to the frame, the sound resampled), and 1.5 s past it when
// the log has the match's end (the half second, and a phrase started a few frames late). A log
// without its end (--until, a killed match) says nothing of how long the sound went on.
constexpr double kShortBy = 0.25, kLongBy = 1.5;

// Throws when `wav`'s length cannot be the sound of the match `events` logs up to `last`.
void check_length(const std::string& wav, double wav_seconds, const std::string& events, double last, bool ended) {
  const bool short_of = wav_seconds < last - kShortBy, past = ended && wav_seconds > last + kLongBy;
  if (!short_of && !past) return;
  char why[400];
  std::snprintf(why, sizeof why,
                "%s is %.1f s of sound, but %s's match %s at %.1f s (its last event or phrase): not the sound of that "
                "match, which would end %.2f s %s that at the %s",
                wav.c_str(), wav_seconds, events.c_str(), ended ? "ends" : "is still on", last, short_of ? kShortBy : kLongBy,
                short_of ? "before" : "after", short_of ? "earliest" : "latest");
  throw std::runtime_error(why);
}

}  // namespace

bool Heard::heard() const { return (" " + recognised + " ").find(" " + words + " ") != std::string::npos; }

int Listening::heard() const {
  return int(std::count_if(played.begin(), played.end(), [](const Heard& h) { return h.heard(); }));
}

Listening listen(const std::string& wav, const std::string& events) {
  // Plain or gzip-compressed; a last line cut short by a killed match is left out, with a warning.
  runtime::LineReader log(events);
  Listening l;
  std::vector<std::string> grammar;  // every phrase's words, once
  std::string line;
  double last = 0;  // the log's last moment: its last event, or the end of its last phrase
  bool ended = false;
  while (log.next(line)) {
    const size_t n = log.number();
    if (line.empty()) continue;
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error(events + ":" + std::to_string(n) + ": not JSON: " + e.what());
    }
    if (j.contains("t") && j["t"].is_number()) last = std::max(last, j["t"].get<double>());
    ended = ended || j.value("type", "") == "match_end";
    for (const auto& p : j.value("phrases", nlohmann::json::array()))
      if (p.contains("end") && p["end"].is_number()) last = std::max(last, p["end"].get<double>());
    if (!j.contains("said")) continue;
    if (!j.contains("phrases"))
      throw std::runtime_error(events + ":" + std::to_string(n) + ": no \"phrases\": log the match with sound "
                                                                 "(--audio wav:FILE) to know which were played");
    const std::string event = j.value("type", "");
    for (const auto& p : j["phrases"]) {
      ++l.said;
      Heard h;
      h.t = j.value("t", 0.0), h.text = p.value("text", ""), h.words = words_of(h.text);
      h.fate = p.value("fate", ""), h.event = event;
      if (!h.words.empty() && std::find(grammar.begin(), grammar.end(), h.words) == grammar.end())
        grammar.push_back(h.words);
      const bool goal = event == "goal" || event == "own_goal";
      l.goal_calls += goal;
      if (h.fate != "spoken" && h.fate != "cut") continue;
      h.start = p.value("start", 0.0), h.end = p.value("end", 0.0);
      if (!h.words.empty()) l.played.push_back(h);
    }
  }
  if (const std::string torn = log.torn(); !torn.empty()) std::cerr << "quantum listen: warning: " << torn << '\n';
  const std::vector<int16_t> sound = mono_16k(wav);
  check_length(wav, double(sound.size()) / kRate, events, last, ended);
  if (grammar.empty()) return l;

  Decoder d;
  // Beams far wider than pocketsphinx's defaults (1e-48, 7e-29, 1e-48): on espeak-ng's voice the
  // defaults pruned the right phrase away before its end, and the recognizer picked nothing at all
  // ("Goal! 11 from 17", whose "Goal!" is followed by a long pause). A grammar of a match's phrases
  // is small, so the wider search costs little (a 60 s match: 1.9 s -> 2.2 s).
  cmd_ln_t* config = cmd_ln_init(nullptr, ps_args(), TRUE, "-hmm", (std::string(kModel) + "/en-us").c_str(), "-dict",
                                 (std::string(kModel) + "/cmudict-en-us.dict").c_str(), "-beam", "1e-80", "-wbeam",
                                 "1e-60", "-pbeam", "1e-80", "-logfn", "/dev/null", nullptr);
  if (!config || !(d.ps = ps_init(config)))
    throw std::runtime_error(std::string("cannot start pocketsphinx with its US English model in ") + kModel +
                             " (Debian: pocketsphinx-en-us)");
  cmd_ln_free_r(config);
  // Every word as the dictionary says it and as espeak-ng's English voices say it: a variant is
  // a word of its own, "clara_2" (alternative pronunciations added at run time upset
  // sphinxbase's grammar), and the grammar takes any of them.
  std::set<std::string> words;
  for (const std::string& phrase : grammar)
    for (const std::string& w : split(phrase)) words.insert(w);
  audio::Speech speech;
  std::map<std::string, std::string> any_of;  // word -> "(clara | clara_2)"
  for (const std::string& w : words) {
    std::vector<std::string> known;
    if (std::string phones = d.lookup(w); !phones.empty()) known.push_back(phones);
    else l.unknown_words.push_back(w);
    for (const char* voice : {"en-us", "en"})
      if (std::string phones = arpabet(speech.ipa(w, voice));
          !phones.empty() && std::find(known.begin(), known.end(), phones) == known.end())
        known.push_back(phones);
    std::string& alternatives = any_of[w];
    for (size_t k = 0; k < known.size(); ++k) {
      const std::string name = k == 0 ? w : w + "_" + std::to_string(k + 1);
      if (k > 0 || d.lookup(w).empty()) ps_add_word(d.ps, name.c_str(), known[k].c_str(), 0);
      alternatives += (k ? " | " : "(") + name;
    }
    alternatives += ")";
  }
  std::string jsgf = "#JSGF V1.0;\ngrammar phrases;\npublic <phrase> = ";
  for (size_t k = 0; k < grammar.size(); ++k) {
    jsgf += k ? " | (" : "(";
    const std::vector<std::string> phrase = split(grammar[k]);
    for (size_t w = 0; w < phrase.size(); ++w) jsgf += (w ? " " : "") + any_of[phrase[w]];
    jsgf += ")";
  }
  jsgf += ";\n";
  if (ps_set_jsgf_string(d.ps, "phrases", jsgf.c_str()) < 0 || ps_set_search(d.ps, "phrases") < 0)
    throw std::runtime_error("pocketsphinx refused the grammar of the match's phrases");
  std::sort(l.played.begin(), l.played.end(), [](const Heard& a, const Heard& b) { return a.start < b.start; });
  for (size_t k = 0; k < l.played.size(); ++k) {
    Heard& h = l.played[k];
    // A little before (a phrase starts in the frame before the one it is logged at) and after
    // (its tail), but none of the phrases either side: the grammar takes one phrase at a time.
    const double before = k > 0 ? l.played[k - 1].end : 0, after = k + 1 < l.played.size() ? l.played[k + 1].start : 1e9;
    const size_t from = size_t(std::max({0.0, before, h.start - 0.05}) * kRate);
    const size_t to = std::min(sound.size(), size_t(std::max(0.0, std::min(h.end + 0.15, after - 0.02)) * kRate));
    if (from >= to) continue;
    // One utterance, fed in blocks as from a microphone: a pause inside a phrase ("Goal! 2
    // from 2") must not split it, since the grammar holds whole phrases.
    ps_start_utt(d.ps);
    for (size_t at = from; at < to; at += 2048)
      ps_process_raw(d.ps, sound.data() + at, std::min<size_t>(2048, to - at), FALSE, FALSE);
    ps_end_utt(d.ps);
    const char* hyp = ps_get_hyp(d.ps, nullptr);
    h.recognised = hyp ? base_words(hyp) : "";
    if (h.event == "goal" || h.event == "own_goal") l.goal_calls_heard += h.heard();
  }
  return l;
}

void report(const Listening& l, std::ostream& out) {
  char buf[64];
  for (const Heard& h : l.played) {
    std::snprintf(buf, sizeof buf, "%4d:%05.2f  ", int(h.t / 60), h.t - 60 * int(h.t / 60));
    out << buf << (h.heard() ? "heard   " : "MISSED  ") << h.text;
    if (h.fate == "cut") out << "  (cut off)";
    if (!h.heard()) out << "  -> " << (h.recognised.empty() ? "nothing" : "\"" + h.recognised + "\"");
    out << '\n';
  }
  const int played = int(l.played.size());
  std::snprintf(buf, sizeof buf, "%.0f %%", played ? 100.0 * l.heard() / played : 100.0);
  out << "heard " << l.heard() << " of " << played << " phrases played (" << buf << "), goal calls " << l.goal_calls_heard
      << " of " << l.goal_calls << "; " << l.said - played << " of " << l.said << " phrases said were not played\n";
  if (!l.unknown_words.empty()) {
    out << "not in the recognizer's dictionary (heard as espeak-ng says them):";
    for (const std::string& w : l.unknown_words) out << ' ' << w;
    out << '\n';
  }
}

}  // namespace quantum::tools
