MeshVersionFormatted 2
SolAtVertices
1
1 1
1
End
