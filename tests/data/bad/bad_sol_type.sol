MeshVersionFormatted 2
Dimension 3
SolAtVertices
2
2 1 7
1 2
3 4
End
