// The desk's window (OpenCV's highgui, Qt in Debian's build): it shows the picture of the match,
// and takes the keys and the mouse a designer plays with.
#pragma once

#include <opencv2/core.hpp>

#include <string>

namespace quantum::runtime {

class Window {
 public:
  // Opens a window on the display. Throws std::runtime_error when there is no display to open
  // it on (no DISPLAY), saying how to render without one.
  explicit Window(const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Shows `image`, waiting up to `wait_ms` for a key; returns the key (-1 for none).
  int show(const cv::Mat& image, int wait_ms = 1);
  // Whether the person closed the window.
  bool closed() const;

  // The mouse over the image, in its pixels; `clicks` counts the presses since the last call.
  struct Mouse {
    int x = -1, y = -1;
    bool over = false;
    int clicks = 0;
  };
  Mouse mouse();

 private:
  static void on_mouse(int event, int x, int y, int flags, void* self);
  std::string title_;
  Mouse mouse_;
  bool shown_ = false;
};

}  // namespace quantum::runtime
