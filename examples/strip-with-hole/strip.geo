// A full strip of 40 × 100 mm with a 10 mm hole off its axis, for tricot's custom tests (lengths in mm).
// The physical curves name the boundaries that case.toml holds and pulls.
SetFactory("OpenCASCADE");
Rectangle(1) = {-20, -50, 0, 40, 100};
Disk(2) = {5, 10, 0, 5, 5};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
eps = 1e-6;
bottom() = Curve In BoundingBox{-20 - eps, -50 - eps, -eps, 20 + eps, -50 + eps, eps};
top() = Curve In BoundingBox{-20 - eps, 50 - eps, -eps, 20 + eps, 50 + eps, eps};
Physical Surface("strip") = {3};
Physical Curve("bottom") = {bottom()};
Physical Curve("top") = {top()};
