#include "window.h"

#include <opencv2/highgui.hpp>

#include <cstdlib>
#include <stdexcept>

namespace quantum::runtime {

Window::Window(const std::string& title) : title_(title) {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    throw std::runtime_error("--view needs a display, and DISPLAY is not set (--video FILE.mp4 renders the match "
                             "without one; xvfb-run gives a virtual one)");
  cv::namedWindow(title_, cv::WINDOW_AUTOSIZE | cv::WINDOW_GUI_NORMAL);
  cv::setMouseCallback(title_, on_mouse, this);
}

Window::~Window() { cv::destroyWindow(title_); }

void Window::on_mouse(int event, int x, int y, int, void* self) {
  auto* w = static_cast<Window*>(self);
  w->mouse_.x = x, w->mouse_.y = y, w->mouse_.over = true;
  if (event == cv::EVENT_LBUTTONDOWN) ++w->mouse_.clicks;
}

int Window::show(const cv::Mat& image, int wait_ms) {
  if (closed()) return -1;  // imshow would open it again
  cv::imshow(title_, image);
  shown_ = true;
  return cv::waitKey(std::max(1, wait_ms));
}

bool Window::closed() const {
  return shown_ && cv::getWindowProperty(title_, cv::WND_PROP_VISIBLE) < 1;
}

Window::Mouse Window::mouse() {
  Mouse m = mouse_;
  mouse_.clicks = 0;
  return m;
}

}  // namespace quantum::runtime
