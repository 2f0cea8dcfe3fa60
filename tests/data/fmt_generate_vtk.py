#!/usr/bin/env python3
"""Generates the binary VTK test files from the format descriptions (struct,
base64 and zlib only, independent of anisurf's writers).

Run from tests/data:  python3 fmt_generate_vtk.py
Good files: fmt_vtk_zlib_be.vtp (big-endian, UInt32 headers, zlib blocks,
  inline base64), fmt_vtk_appended.vtu (appended raw, UInt64 headers),
  fmt_legacy_bin.vtk (legacy BINARY POLYDATA, big-endian).
Broken files (tests/data/bad): bad_vtu_zlib_block.vtu, bad_vtu_appended_size.vtu,
  bad_vtk_truncated.vtk, bad_msh_truncated.msh, bad_msh_huge_count.msh
"""
import base64
import struct
import zlib


def zlib_blocks(raw, order, block=16):
    """vtkZLibDataCompressor layout: [nblocks, blocksize, lastsize, csizes] + data."""
    chunks = [raw[i:i + block] for i in range(0, len(raw), block)]
    comp = [zlib.compress(c) for c in chunks]
    last = len(raw) % block
    head = struct.pack(order + "%dI" % (3 + len(comp)), len(comp), block, last, *[len(c) for c in comp])
    return base64.b64encode(head).decode() + base64.b64encode(b"".join(comp)).decode()


def vtp_zlib_be():
    """PolyData: a triangle, a quad (skipped), a polyline of 3 points (2 edges)."""
    o = ">"
    pts = struct.pack(o + "15d", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1.0 / 3.0)

    def arr(typ, name, ncomp, raw):
        nc = ' NumberOfComponents="%d"' % ncomp if ncomp != 1 else ""
        return '<DataArray type="%s" Name="%s"%s format="binary">%s</DataArray>\n' % (
            typ, name, nc, zlib_blocks(raw, o))

    x = '<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="BigEndian" ' \
        'header_type="UInt32" compressor="vtkZLibDataCompressor">\n<PolyData>\n' \
        '<Piece NumberOfPoints="5" NumberOfVerts="0" NumberOfLines="1" NumberOfStrips="0" NumberOfPolys="2">\n'
    x += "<PointData>\n" + arr("Float64", "speed", 3, struct.pack(o + "15d", *range(15))) + "</PointData>\n"
    x += "<CellData>\n" + arr("Int64", "ref", 1, struct.pack(o + "3q", 4, 6, 0)) + "</CellData>\n"
    x += "<Points>\n" + arr("Float64", "Points", 3, pts) + "</Points>\n"
    x += "<Lines>\n" + arr("Int64", "connectivity", 1, struct.pack(o + "3q", 0, 1, 2)) + \
         arr("Int64", "offsets", 1, struct.pack(o + "q", 3)) + "</Lines>\n"
    x += "<Polys>\n" + arr("Int32", "connectivity", 1, struct.pack(o + "7i", 0, 1, 4, 0, 1, 2, 3)) + \
         arr("Int32", "offsets", 1, struct.pack(o + "2i", 3, 7)) + "</Polys>\n"
    x += "</Piece>\n</PolyData>\n</VTKFile>\n"
    return x.encode()


def vtu_appended(bad_size=False):
    """UnstructuredGrid with appended raw data, UInt64 headers, Float32 points."""
    blobs = []
    arrays = []

    def arr(typ, name, ncomp, raw, xml_list):
        offset = sum(len(b) for b in blobs)
        size = len(raw) + (8 if bad_size and name == "connectivity" else 0)
        blobs.append(struct.pack("<Q", size) + raw)
        nc = ' NumberOfComponents="%d"' % ncomp if ncomp != 1 else ""
        xml_list.append('<DataArray type="%s" Name="%s"%s format="appended" offset="%d"/>\n' % (
            typ, name, nc, offset))

    pd, cd, pts, cells = [], [], [], []
    arr("Float32", "Points", 3, struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0), pts)
    arr("Int64", "connectivity", 1, struct.pack("<6q", 0, 1, 2, 0, 2, 3), cells)
    arr("Int64", "offsets", 1, struct.pack("<2q", 3, 6), cells)
    arr("UInt8", "types", 1, struct.pack("<2B", 5, 5), cells)
    arr("Float64", "T", 9, struct.pack("<36d", *([1, 0, 0, 0, 1, 0, 0, 0, 1] * 3 + [2, 1, 0, 1, 2, 0, 0, 0, 2])), pd)
    arr("UInt16", "medit:ref", 1, struct.pack("<2H", 3, 65535), cd)
    x = '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" ' \
        'header_type="UInt64">\n<UnstructuredGrid>\n<Piece NumberOfPoints="4" NumberOfCells="2">\n'
    x += "<PointData>\n" + "".join(pd) + "</PointData>\n<CellData>\n" + "".join(cd) + "</CellData>\n"
    x += "<Points>\n" + "".join(pts) + "</Points>\n<Cells>\n" + "".join(cells) + "</Cells>\n"
    x += '</Piece>\n</UnstructuredGrid>\n<AppendedData encoding="raw">\n_'
    return x.encode() + b"".join(blobs) + b"\n</AppendedData>\n</VTKFile>\n"


def legacy_bin():
    """Legacy BINARY POLYDATA (big-endian): 4 points, a line, 2 polygons."""
    b = b"# vtk DataFile Version 3.0\nbinary polydata\nBINARY\nDATASET POLYDATA\n"
    b += b"POINTS 4 float\n" + struct.pack(">12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0) + b"\n"
    b += b"LINES 1 3\n" + struct.pack(">3i", 2, 0, 1) + b"\n"
    b += b"POLYGONS 2 8\n" + struct.pack(">8i", 3, 0, 1, 2, 3, 0, 2, 3) + b"\n"
    b += b"CELL_DATA 3\nSCALARS ref int 1\nLOOKUP_TABLE default\n" + struct.pack(">3i", 1, 2, 3) + b"\n"
    b += b"POINT_DATA 4\nVECTORS v double\n" + struct.pack(">12d", *range(12)) + b"\n"
    b += b"SCALARS vertex_ref int 1\nLOOKUP_TABLE default\n" + struct.pack(">4i", 0, 5, 0, 0) + b"\n"
    return b


def bad_vtu_zlib_block():
    """A zlib block whose bytes are not a zlib stream."""
    good = zlib_blocks(struct.pack("<3q", 0, 1, 2), "<", block=64)
    raw = base64.b64decode(good[:24])  # the header: 1 block
    bogus = base64.b64encode(raw).decode() + base64.b64encode(b"not zlib data at all").decode()
    x = '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" byte_order="LittleEndian" ' \
        'compressor="vtkZLibDataCompressor">\n<UnstructuredGrid>\n<Piece NumberOfPoints="3" NumberOfCells="1">\n' \
        '<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray>' \
        '</Points>\n<Cells>\n' \
        '<DataArray type="Int64" Name="connectivity" format="binary">%s</DataArray>\n' \
        '<DataArray type="Int64" Name="offsets" format="ascii">3</DataArray>\n' \
        '<DataArray type="UInt8" Name="types" format="ascii">5</DataArray>\n' \
        '</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n' % bogus
    return x.encode()


def bad_msh_truncated():
    """Binary MSH 4.1 cut inside the node coordinates."""
    b = b"$MeshFormat\n4.1 1 8\n" + struct.pack("<i", 1) + b"\n$EndMeshFormat\n$Nodes\n"
    b += struct.pack("<4Q", 1, 3, 1, 3) + struct.pack("<iiiQ", 2, 1, 0, 3) + struct.pack("<3Q", 1, 2, 3)
    b += struct.pack("<4d", 0, 0, 0, 1)
    return b


def bad_msh_huge_count():
    """Binary MSH 2.2 announcing 2e9 nodes in a tiny file."""
    return b"$MeshFormat\n2.2 1 8\n" + struct.pack("<i", 1) + b"\n$EndMeshFormat\n$Nodes\n2000000000\n" + \
        struct.pack("<i3d", 1, 0, 0, 0) + b"\n$EndNodes\n"


if __name__ == "__main__":
    for name, data in [("fmt_vtk_zlib_be.vtp", vtp_zlib_be()), ("fmt_vtk_appended.vtu", vtu_appended()),
                       ("fmt_legacy_bin.vtk", legacy_bin()),
                       ("bad/bad_vtu_zlib_block.vtu", bad_vtu_zlib_block()),
                       ("bad/bad_vtu_appended_size.vtu", vtu_appended(bad_size=True)),
                       ("bad/bad_vtk_truncated.vtk", legacy_bin()[:150]),
                       ("bad/bad_msh_truncated.msh", bad_msh_truncated()),
                       ("bad/bad_msh_huge_count.msh", bad_msh_huge_count())]:
        with open(name, "wb") as f:
            f.write(data)
