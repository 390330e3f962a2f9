// Glass plate 100 mm x 40 mm for the crack-branching benchmark of adaptive
// refinement (docs/refinement.md): the pre-crack, 50 mm from the left edge at
// mid-height, is a [[precracks]] entry of glass_plate.toml. Built-in kernel.
// Units: mm. Boundary sets from pd-mesh: left, right, bottom, top.
W = 100;
H = 40;
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
