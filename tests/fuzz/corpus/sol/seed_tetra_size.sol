MeshVersionFormatted 2

Dimension 3

# anisurf field names: metric

SolAtVertices
5
1 3

4 0 4 0 0 4
4 0 4 0 0 4
4 0 4 0 0 4
4 0 4 0 0 4
4 0 4 0 0 4

End
