// Case C3-A: PMMA plate 50 mm x 25 mm with 8 periodic pores of radius 0.75 mm
// [Peng, Chen, Bobaru 2023, Sec. 5]. Pore spacing D = W/9, centres at x = k D (k = 1..8), assumed.
// Case A: one row on the mid-line y = H/2.
// The pre-crack is not geometry: it is set in the scene (c3a_long.toml, c3a_short.toml).
// OpenCASCADE kernel. Units: mm.
SetFactory("OpenCASCADE");
W = 50; H = 25; R = 0.75; D = W / 9;
Rectangle(1) = {0, 0, 0, W, H};
For k In {1:8}
  Disk(1 + k) = {k * D, H / 2, 0, R, R};
EndFor
BooleanDifference(100) = { Surface{1}; Delete; }{ Surface{2:9}; Delete; };
