// SPDX-License-Identifier: Apache-2.0
// The bundled liver meshed conformally with its drawn surface for the FEM reference of the
// organ poke (tissuesim organ-poke): Gmsh remeshes the surface and fills it with tets, graded
// towards the point where the bundled scene's probe meets the surface. Run by make-liver-fem.sh,
// which writes the surface in metres to liver-smooth-m.stl first.
DefineConstant[
  finest = {0.001, Name "finest tet edge at the poke (m)"},
  growth = {0.3, Name "edge growth per metre from the poke"},
  coarsest = {0.008, Name "coarsest tet edge (m)"},
  px = {0.0, Name "poke x"}, py = {0.1439, Name "poke y"}, pz = {0.045, Name "poke z"}
];
Merge "liver-smooth-m.stl";
// One smooth surface, reparametrised so it can be remeshed (a feature angle below 180 degrees
// split the liver into patches whose remeshed boundaries crossed).
ClassifySurfaces{Pi, 1, 1, Pi};
CreateGeometry;
Surface Loop(1) = Surface{:};
Volume(1) = {1};
Field[1] = MathEval;
// Each coordinate in brackets: Gmsh's MathEval refuses "x - -0.04".
Field[1].F = Sprintf("%g + %g * sqrt((x - (%g)) * (x - (%g)) + (y - (%g)) * (y - (%g)) + (z - (%g)) * (z - (%g)))",
                     finest, growth, px, px, py, py, pz, pz);
Background Field = 1;
Mesh.MeshSizeMax = coarsest;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Optimize = 1;
Mesh.MshFileVersion = 2.2;
