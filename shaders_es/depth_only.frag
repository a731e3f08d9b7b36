#version 300 es
// Writes depth alone: no colour output, so the rasteriser runs no shading for phantoms.
precision mediump float;

void main()
{
}
