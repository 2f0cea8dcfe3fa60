MeshVersionFormatted 2
Dimension 3
SolAtVertices
3
1 3
1 0 1 0 0 1
1 0 1 0 0 1
1 0 1
