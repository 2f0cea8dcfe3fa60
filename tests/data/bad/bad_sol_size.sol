MeshVersionFormatted 2

Dimension 3

SolAtVertices
5
1 1

1
2
3
4
5

End
