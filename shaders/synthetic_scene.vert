#version 430 core
// The synthetic street of src/gpu/synthetic_scene.cpp: world-space triangles projected with
// pluvia's pinhole camera (uClipFromWorld maps image row 0 to window row 0, so read-back needs
// no flip), or, with uSky, one triangle covering the whole frame for the sky.
layout(location = 0) in vec3 aPositionMeters;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aSurface;

uniform bool uSky;
uniform mat4 uClipFromWorld;

out vec3 vWorldMeters;
flat out vec3 vNormal;
flat out float vSurface;

void main() {
  if (uSky) {
    // Vertices 0, 1, 2 -> (-1,-1), (3,-1), (-1,3): covers the viewport with one triangle.
    vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
    vWorldMeters = vec3(0.0);
    vNormal = vec3(0.0, 1.0, 0.0);
    vSurface = -1.0;
    return;
  }
  vWorldMeters = aPositionMeters;
  vNormal = aNormal;
  vSurface = aSurface;
  gl_Position = uClipFromWorld * vec4(aPositionMeters, 1.0);
}
