#pragma once
// One input event, from the window (GLFW callbacks) or from a script: both go through the same
// handler, so a scripted session exercises what a user does.

#include <string>

namespace lacet::ui {

struct InputEvent {
    enum class Type { MouseDown, MouseUp, MouseMove, Scroll, Key } type = Type::MouseMove;
    double x = 0.0, y = 0.0;  // window pixels (mouse events), or the scroll offsets
    int button = 0;           // 0 left, 1 right, 2 middle
    int key = 0;              // GLFW key code
    int mods = 0;             // GLFW modifier bits
};

}  // namespace lacet::ui
