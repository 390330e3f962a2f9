// Case C1/C2: 20 mm x 20 mm plate with a central circular hole of diameter 8 mm
// [Peng, Chen, Bobaru 2023, Sec. 4.1]. Built-in kernel. Units: mm (pd-mesh --geo-unit, default mm).
// Boundary sets left/right/bottom/top/hole_1 are created by pd-mesh automatically.
W = 20; H = 20; R = 4;
Point(1) = {0, 0, 0};
Point(2) = {W, 0, 0};
Point(3) = {W, H, 0};
Point(4) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};

Point(5) = {W/2, H/2, 0};
Point(6) = {W/2 + R, H/2, 0};
Point(7) = {W/2, H/2 + R, 0};
Point(8) = {W/2 - R, H/2, 0};
Point(9) = {W/2, H/2 - R, 0};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(2) = {5, 6, 7, 8};

Plane Surface(1) = {1, 2};
