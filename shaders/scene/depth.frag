#version 460
// Depth only (shadow maps): the fixed-function depth write does the work.
void main() {}
