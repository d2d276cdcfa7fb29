#pragma once
// A derain window short enough for its camera to register: every frame of a window is
// registered onto its middle one, and a camera that crosses a large part of the frame within the
// window leaves the ends too little overlap (a vehicle's camera moving about 60 px a frame at
// 640 px: its 20-frame windows failed to register, and their clean plates came out ghosted).

namespace pluvia::derain {

// The longest odd window, at most `window` and at least 3 frames, whose ends lie within
// kMaxSpanOfWidth of the frame's width of its middle frame at `shiftPerFramePx`.
inline constexpr double kMaxSpanOfWidth = 0.25;
int windowForCameraSpeed(int window, double shiftPerFramePx, int widthPx);

}  // namespace pluvia::derain
