#include "window.h"

#include <X11/Xlib.h>

#include <opencv2/highgui.hpp>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace quantum::runtime {
namespace {

// The screen's size in pixels, or an error naming DISPLAY when there is no X server to ask:
// asked first because highgui's Qt aborts the process (exit 134) on a display it cannot open.
cv::Size screen_size() {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    throw std::runtime_error("--view needs a display, and DISPLAY is not set (--video FILE.mp4 renders the match "
                             "without one; xvfb-run gives a virtual one)");
  Display* x = XOpenDisplay(nullptr);
  if (!x)
    throw std::runtime_error(std::string("--view needs a display, and DISPLAY=") + display +
                             " cannot be opened (no X server there, or not allowed: check DISPLAY and xauth; "
                             "--video FILE.mp4 renders the match without one)");
  const int screen = DefaultScreen(x);
  const cv::Size size(DisplayWidth(x, screen), DisplayHeight(x, screen));
  XCloseDisplay(x);
  return size;
}

// highgui gives a key its X keysym (both the GTK and the Qt build) when it has no character.
int special_key(int code) {
  switch (code) {
    case 0xFF51: return kKeyLeft;
    case 0xFF53: return kKeyRight;
    case 0xFF52: return kKeyUp;
    case 0xFF54: return kKeyDown;
    case 0xFF50: return kKeyHome;
    case 0xFF57: return kKeyEnd;
    case 0xFF0D: case 0xFF8D: case '\r': case '\n': return kKeyEnter;
    case 0xFF1B: case 27: return kKeyEscape;
    default: return code;
  }
}

}  // namespace

Window::Window(const std::string& title, cv::Size aspect) : title_(title), screen_(screen_size()) {
  cv::namedWindow(title_, cv::WINDOW_NORMAL | (aspect.empty() ? cv::WINDOW_FREERATIO : cv::WINDOW_KEEPRATIO) |
                              cv::WINDOW_GUI_NORMAL);
  const cv::Size size = fitting(aspect);
  cv::resizeWindow(title_, size.width, size.height);
  cv::setMouseCallback(title_, on_mouse, this);
}

Window::~Window() { cv::destroyWindow(title_); }

cv::Size Window::fitting(cv::Size aspect) const {
  // Room for the window's title bar and the desktop's panels, which X does not tell apart.
  const double room_x = 0.95 * screen_.width, room_y = 0.88 * screen_.height;
  if (aspect.empty()) return {int(room_x), int(room_y)};
  const double scale = std::min(room_x / std::max(1, aspect.width), room_y / std::max(1, aspect.height));
  return {std::max(1, int(aspect.width * scale)), std::max(1, int(aspect.height * scale))};
}

cv::Size Window::size() const {
  const cv::Rect area = cv::getWindowImageRect(title_);
  return area.width > 0 && area.height > 0 ? area.size() : cv::Size();
}

void Window::toggle_full_screen() {
  full_screen_ = !full_screen_;
  cv::setWindowProperty(title_, cv::WND_PROP_FULLSCREEN, full_screen_ ? cv::WINDOW_FULLSCREEN : cv::WINDOW_NORMAL);
}

void Window::on_mouse(int event, int x, int y, int flags, void* self) {
  auto* w = static_cast<Window*>(self);
  w->mouse_.x = x, w->mouse_.y = y, w->mouse_.over = true;
  if (event == cv::EVENT_LBUTTONDOWN) ++w->mouse_.clicks;
  w->mouse_.down = (flags & cv::EVENT_FLAG_LBUTTON) != 0 && event != cv::EVENT_LBUTTONUP;
}

int Window::show(const cv::Mat& image, int wait_ms) {
  if (closed()) return kKeyNone;  // imshow would open it again
  cv::imshow(title_, image);
  shown_ = true;
  return special_key(cv::waitKeyEx(std::max(1, wait_ms)));
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
