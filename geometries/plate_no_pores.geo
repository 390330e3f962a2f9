// PMMA plate 50 mm x 25 mm without pores (static-then-dynamic check, case C3 App. 3
// of [Peng, Chen, Bobaru 2023]). Built-in kernel. Units: mm.
W = 50; H = 25;
Point(1) = {0, 0, 0};
Point(2) = {W, 0, 0};
Point(3) = {W, H, 0};
Point(4) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
