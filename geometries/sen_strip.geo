// Single-edge-notch strip: a strip 20 mm wide and 40 mm tall with an edge
// notch from the middle of its left side, 5 mm long (tip at x = 5 mm) and
// 1 mm wide, ending in a half circle of radius 0.5 mm. Pulled apart at its
// ends (sen_strip.toml). Built-in kernel. Units: mm.
// Boundary sets from pd-mesh: left (the two parts of the left side beside
// the notch's mouth), right, bottom, top; "notch" names the notch's faces.
W = 20; H = 40; a = 5; w = 1;
Point(1) = {0, 0, 0};
Point(2) = {W, 0, 0};
Point(3) = {W, H, 0};
Point(4) = {0, H, 0};
Point(5) = {0, H/2 + w/2, 0};
Point(6) = {a - w/2, H/2 + w/2, 0};
Point(7) = {a - w/2, H/2, 0};  // centre of the tip
Point(8) = {a, H/2, 0};
Point(9) = {a - w/2, H/2 - w/2, 0};
Point(10) = {0, H/2 - w/2, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Circle(6) = {6, 7, 8};
Circle(7) = {8, 7, 9};
Line(8) = {9, 10};
Line(9) = {10, 1};
Curve Loop(1) = {1:9};
Plane Surface(1) = {1};
Physical Curve("notch") = {5, 6, 7, 8};
