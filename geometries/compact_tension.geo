// Compact-tension specimen in the proportions of ASTM E399 with W = 50 mm:
// 62.5 mm (1.25 W) wide, 60 mm (1.2 W) tall; pin holes of diameter 12.5 mm
// (0.25 W) centred 12.5 mm (0.25 W) from the front edge and 13.75 mm
// (0.275 W) above and below the notch line; a notch from the front edge
// (x = 0) along y = 30 mm, 1.5 mm wide, whose half-circle tip lies at
// x = 37.5 mm, i.e. a = 25 mm = 0.5 W from the pins' line. The pins pull
// the holes apart (compact_tension.toml). Built-in kernel. Units: mm.
// Boundary sets from pd-mesh: left (front edge beside the notch), right,
// bottom, top, hole_1 (lower pin hole), hole_2 (upper pin hole); "notch".
W = 50; B = 1.25 * W; H = 1.2 * W; a = 0.5 * W; w = 1.5; R = 0.125 * W;
x_pin = 0.25 * W; y_mid = H / 2; y_pin = 0.275 * W; x_tip = x_pin + a;
Point(1) = {0, 0, 0};
Point(2) = {B, 0, 0};
Point(3) = {B, H, 0};
Point(4) = {0, H, 0};
Point(5) = {0, y_mid + w/2, 0};
Point(6) = {x_tip - w/2, y_mid + w/2, 0};
Point(7) = {x_tip - w/2, y_mid, 0};  // centre of the tip
Point(8) = {x_tip, y_mid, 0};
Point(9) = {x_tip - w/2, y_mid - w/2, 0};
Point(10) = {0, y_mid - w/2, 0};
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
// Pin holes, lower (hole_1) and upper (hole_2).
For k In {0:1}
  yc = y_mid + (2 * k - 1) * y_pin;
  c = newp; Point(c) = {x_pin, yc, 0};
  p1 = newp; Point(p1) = {x_pin + R, yc, 0};
  p2 = newp; Point(p2) = {x_pin - R, yc, 0};
  c1 = newc; Circle(c1) = {p1, c, p2};
  c2 = newc; Circle(c2) = {p2, c, p1};
  hole[k] = newll; Curve Loop(hole[k]) = {c1, c2};
EndFor
Plane Surface(1) = {1, hole[0], hole[1]};
Physical Curve("notch") = {5, 6, 7, 8};
