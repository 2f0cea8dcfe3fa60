MeshVersionFormatted 2
Dimension 2
SolAtVertices
3
1 3
1 0 1
1 NaN 1
1 0 1
End
