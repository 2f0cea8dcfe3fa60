MeshVersionFormatted 2
Dimension 3
SolAtVertices
4
2 1 2
0.5 1 0 0
0.25 0 1 0
0.125 0 0 1
1 1 1 0
End
