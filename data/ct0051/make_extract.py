# Makes data/ct0051/ct0051_z040-100.inv3 from the package's Cranium.inv3.
import gzip, hashlib, io, re, sys, tarfile
src, out = sys.argv[1], sys.argv[2]
Z0, Z1 = 40, 100                     # inclusive slice range of the original 108
with tarfile.open(src, "r:gz") as t:
    names = {m.name.split("/")[-1]: m for m in t.getmembers()}
    plist = t.extractfile(names["main.plist"]).read().decode().replace("\r\n", "\n")  # CRLF -> LF
    matrix = t.extractfile(names["matrix.dat"]).read()
assert hashlib.sha256(matrix).hexdigest() == "d87fd5e6aaf2c4fdf4f3fe28ee3335192fc2464ed8e9682fc78530cb837938da"
S = 256 * 256 * 2
sub = matrix[Z0 * S:(Z1 + 1) * S]
n = Z1 - Z0 + 1
plist = plist.replace("<integer>108</integer>", "<integer>%d</integer>" % n, 1)
# drop references to files that are not in the extract (masks, surfaces, measurements)
plist = re.sub(r"\t<key>masks</key>\n\t<dict>.*?\n\t</dict>\n", "\t<key>masks</key>\n\t<dict>\n\t</dict>\n", plist, flags=re.S)
plist = re.sub(r"\t<key>surfaces</key>\n\t<dict>.*?\n\t</dict>\n", "\t<key>surfaces</key>\n\t<dict>\n\t</dict>\n", plist, flags=re.S)
plist = re.sub(r"\t<key>measurements</key>\n\t<string>measurements.plist</string>\n", "", plist)
plist = plist.replace("<plist version=\"1.0\">", "<!-- metabezier extract: slices z = %d..=%d (inclusive) of the original 108 of Cranium.inv3 -->\n<plist version=\"1.0\">" % (Z0, Z1), 1)
buf = io.BytesIO()
with tarfile.open(fileobj=buf, mode="w", format=tarfile.USTAR_FORMAT) as t:
    for name, data in [("main.plist", plist.encode()), ("matrix.dat", sub)]:
        info = tarfile.TarInfo(name); info.size = len(data); info.mtime = 0; info.mode = 0o644
        t.addfile(info, io.BytesIO(data))
with open(out, "wb") as f:
    with gzip.GzipFile(filename="", mode="wb", fileobj=f, compresslevel=9, mtime=0) as g:
        g.write(buf.getvalue())
print(hashlib.sha256(sub).hexdigest(), len(sub))
