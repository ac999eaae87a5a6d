// The desk's window (OpenCV's highgui, Qt in Debian's build): it shows the picture of the match,
// and takes the keys and the mouse a designer plays with. It opens at a size that fits the
// screen, can be resized and put full screen; the desk draws its picture at the window's size.
#pragma once

#include <opencv2/core.hpp>

#include <string>

namespace quantum::runtime {

// Keys as the window reports them: a character's code, or one of these for the keys that have
// none (highgui's Qt and GTK builds number them differently; Window::show gives these).
enum SpecialKey : int {
  kKeyNone = -1,
  kKeyLeft = 0x10000,
  kKeyRight,
  kKeyUp,
  kKeyDown,
  kKeyHome,
  kKeyEnd,
  kKeyEnter,
  kKeyEscape,
};

class Window {
 public:
  // Opens a window on the display for pictures of `aspect` (their size: only its shape counts),
  // as large as fits the screen with room for its frame and the desktop's panels, shown with
  // their shape kept; an empty `aspect`: as large as the screen has room for, pictures
  // stretched to the window (a desk that draws them at size() keeps them sharp). Throws
  // std::runtime_error, in one line that names DISPLAY, when there is no display to open it on
  // (unset, or no X server there: highgui would abort the process instead).
  Window(const std::string& title, cv::Size aspect);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // The size the picture should be drawn at now: the window's drawing area, which the person
  // may have resized or made full screen (the image is scaled to it, its shape kept, so an
  // image of another size shows too, only less sharp).
  cv::Size size() const;
  // The largest size of the given shape that fits the screen (empty: the screen's room).
  cv::Size fitting(cv::Size aspect) const;
  void toggle_full_screen();
  bool full_screen() const { return full_screen_; }

  // Shows `image`, waiting up to `wait_ms` for a key; returns the key (a character's code, a
  // SpecialKey, or kKeyNone).
  int show(const cv::Mat& image, int wait_ms = 1);
  // Whether the person closed the window.
  bool closed() const;

  // The mouse over the image, in its pixels; `clicks` counts the presses since the last call,
  // `down` whether the left button is held (a drag on the time bar).
  struct Mouse {
    int x = -1, y = -1;
    bool over = false, down = false;
    int clicks = 0;
  };
  Mouse mouse();

 private:
  static void on_mouse(int event, int x, int y, int flags, void* self);
  std::string title_;
  cv::Size screen_;
  Mouse mouse_;
  bool shown_ = false, full_screen_ = false;
};

}  // namespace quantum::runtime
