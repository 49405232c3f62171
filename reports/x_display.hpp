#pragma once
// The X display used for offscreen rendering. Kept apart from render.cpp because Xlib's
// macros (Status, Bool, None) clash with ours.
#include <string>

namespace orthosonar::reports::detail {

// Empty when $DISPLAY is set and its server accepts a connection; otherwise why not.
std::string x_display_problem();

// One connection (an Xlib Display*), opened on first use and kept for the process's life,
// or nullptr. Every render window uses it: an X server (Xvfb) resets when its last client
// disconnects, and a window opening during that reset fails, which VTK answers with
// abort(). Holding one connection open means the server never resets under us.
void* shared_x_display();

}  // namespace orthosonar::reports::detail
