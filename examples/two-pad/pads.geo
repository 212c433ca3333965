// A pad extensometer on a skin-like sheet (issue 28): a 60 × 40 mm region with two 10 × 10 mm holes where
// two pads are glued, and an elliptic lesion of another material between them (lengths in mm). Gmsh
// meshes it with linear triangles; the physical curves name the pads, the physical surfaces the two
// materials.
SetFactory("OpenCASCADE");
Rectangle(1) = {-30, -20, 0, 60, 40};
Rectangle(2) = {-18, -5, 0, 10, 10};   // the fixed pad
Rectangle(3) = {8, -5, 0, 10, 10};     // the moving pad
Disk(4) = {0, 0, 0, 5, 3.5};           // the lesion (OpenCASCADE: the first radius the larger)
BooleanDifference(5) = { Surface{1}; Delete; }{ Surface{2, 3}; Delete; };
BooleanFragments{ Surface{5}; Delete; }{ Surface{4}; Delete; }
eps = 1e-6;
lesion() = Surface In BoundingBox{-5 - eps, -3.5 - eps, -eps, 5 + eps, 3.5 + eps, eps};
all() = Surface{:};
skin() = all();
skin() -= lesion();
Physical Surface("skin") = {skin()};
Physical Surface("lesion") = {lesion()};
Physical Curve("pad_fixed") = Curve In BoundingBox{-18 - eps, -5 - eps, -eps, -8 + eps, 5 + eps, eps};
Physical Curve("pad_moving") = Curve In BoundingBox{8 - eps, -5 - eps, -eps, 18 + eps, 5 + eps, eps};
