#include "reports/x_display.hpp"

#include <cstdlib>
#include <cstring>
#include <mutex>

#include <X11/Xlib.h>

namespace orthosonar::reports::detail {
namespace {

std::mutex g_mutex;
Display* g_display = nullptr;  // never closed: see the header

}  // namespace

void* shared_x_display() {
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || std::strlen(name) == 0) return nullptr;
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_display == nullptr) g_display = XOpenDisplay(name);
  return g_display;
}

std::string x_display_problem() {
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || std::strlen(name) == 0) return "DISPLAY is unset";
  if (shared_x_display() == nullptr) return std::string("cannot connect to X display '") + name + "'";
  return {};
}

}  // namespace orthosonar::reports::detail
