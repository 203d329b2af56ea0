//! InVesalius `.inv3` projects: a gzip-compressed tar holding `main.plist`
//! (an XML property list with `matrix.shape = [nz, ny, nx]`,
//! `matrix.dtype = "int16"`, `matrix.filename` and `spacing = [sx, sy, sz]`
//! in mm) and the raw volume `matrix.dat` (little-endian int16 HU, z/y/x
//! order, no header). Format as written by InVesalius 3 (Amorim et al.,
//! "InVesalius: an interactive rendering framework for health care support",
//! ISVC 2015), `invesalius/project.py`.

use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

use flate2::read::GzDecoder;

use super::error::{CtError, Inv3Problem};
use super::plist::{parse_plist, PlistValue};
use super::volume::{FrameSource, Spacing, Volume, IDENTITY_AXES};
use crate::files::write_atomic;

/// The most bytes deflate can produce per compressed byte: a maximal match
/// of 258 bytes costs at least two bits, so the ratio is bounded by 1,032
/// (RFC 1951; zlib's technical details give the same bound).
const MAX_DEFLATE_RATIO: u64 = 1032;

/// The members of the project's gzip-compressed tar by file name, except
/// masks and surface meshes (which can be large and are not needed).
///
/// Every member's declared size is checked against what the file can hold
/// before anything is allocated, and the gzip stream is read to its end so
/// that its CRC-32 and length trailer (RFC 1952) are verified: a corrupt
/// byte anywhere, in a skipped member or in the padding, is refused.
fn read_members(path: &Path) -> Result<HashMap<String, Vec<u8>>, CtError> {
    let file = std::fs::File::open(path).map_err(|e| CtError::io(path, e))?;
    let file_len = file.metadata().map_err(|e| CtError::io(path, e))?.len();
    let limit = file_len.saturating_mul(MAX_DEFLATE_RATIO);
    let mut archive = tar::Archive::new(GzDecoder::new(std::io::BufReader::new(file)));
    let members = read_entries(&mut archive, path, (file_len, limit))?;
    let mut rest = archive.into_inner();
    std::io::copy(&mut rest, &mut std::io::sink())
        .map_err(|e| CtError::inv3(path, Inv3Problem::Checksum(e)))?;
    Ok(members)
}

/// The wanted members of `archive` (see [`read_members`]), each declared
/// size at most `limit` bytes (a `file_len`-byte gzip file holds no more).
fn read_entries<R: Read>(
    archive: &mut tar::Archive<R>,
    path: &Path,
    (file_len, limit): (u64, u64),
) -> Result<HashMap<String, Vec<u8>>, CtError> {
    let mut members: HashMap<String, Vec<u8>> = HashMap::new();
    let entries = archive
        .entries()
        .map_err(|e| CtError::inv3(path, Inv3Problem::TarStream(e)))?;
    for entry in entries {
        let mut entry = entry.map_err(|e| CtError::inv3(path, Inv3Problem::TarEntry(e)))?;
        let name = entry
            .path()
            .map_err(|e| CtError::inv3(path, Inv3Problem::MemberName(e)))?
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let declared = entry.size();
        if declared > limit {
            return Err(CtError::inv3(
                path,
                Inv3Problem::MemberTooLarge {
                    name,
                    declared,
                    limit,
                    file_len,
                },
            ));
        }
        if name.starts_with("mask_") || name.ends_with(".vtp") {
            continue;
        }
        let mut bytes = Vec::with_capacity(declared as usize);
        entry.read_to_end(&mut bytes).map_err(|source| {
            CtError::inv3(
                path,
                Inv3Problem::Member {
                    name: name.clone(),
                    source,
                },
            )
        })?;
        members.insert(name, bytes);
    }
    Ok(members)
}

/// The parsed `main.plist` member of the project at `path`.
fn main_plist(members: &HashMap<String, Vec<u8>>, path: &Path) -> Result<PlistValue, CtError> {
    let plist_bytes = members
        .get("main.plist")
        .ok_or_else(|| CtError::inv3(path, Inv3Problem::MissingMember("main.plist".into())))?;
    let text = std::str::from_utf8(plist_bytes)
        .map_err(|_| CtError::inv3(path, Inv3Problem::PlistNotUtf8))?;
    parse_plist(text).map_err(|e| CtError::inv3(path, Inv3Problem::Plist(e)))
}

/// The `(nx, ny, nz)` of `matrix.shape = [nz, ny, nx]`, checked to be an
/// int16 matrix of positive size.
fn matrix_shape(matrix: &PlistValue, path: &Path) -> Result<(usize, usize, usize), CtError> {
    let dtype = matrix
        .get("dtype")
        .and_then(PlistValue::as_str)
        .unwrap_or("");
    if dtype != "int16" {
        return Err(CtError::inv3(path, Inv3Problem::Dtype(dtype.into())));
    }
    let shape: Vec<i64> = matrix
        .get("shape")
        .and_then(PlistValue::as_array)
        .map(|a| a.iter().filter_map(PlistValue::as_i64).collect())
        .unwrap_or_default();
    if shape.len() != 3 || shape.iter().any(|&s| s <= 0) {
        return Err(CtError::inv3(path, Inv3Problem::Shape(shape)));
    }
    Ok((shape[2] as usize, shape[1] as usize, shape[0] as usize))
}

/// Reads the CT volume of an `.inv3` project. Masks and surfaces in the
/// project are ignored. The project holds no origin or patient axes (only
/// the spacing and an `orientation` flag, kept in
/// [`FrameSource::Inv3`]), so the volume's frame is the identity at 0. Errors name the file: a corrupt or truncated gzip/tar
/// stream, a missing `main.plist` or matrix, a malformed plist, a dtype other
/// than int16, or a matrix whose byte count is not `2·nx·ny·nz`.
pub fn read_inv3(path: &Path) -> Result<Volume, CtError> {
    let members = read_members(path)?;
    let plist = main_plist(&members, path)?;
    let matrix = plist
        .get("matrix")
        .ok_or_else(|| CtError::inv3(path, Inv3Problem::NoMatrix))?;
    let (nx, ny, nz) = matrix_shape(matrix, path)?;
    let spacing: Vec<f64> = plist
        .get("spacing")
        .and_then(PlistValue::as_array)
        .map(|a| a.iter().filter_map(PlistValue::as_f64).collect())
        .unwrap_or_default();
    if spacing.len() != 3 || spacing.iter().any(|&s| !(s.is_finite() && s > 0.0)) {
        return Err(CtError::inv3(path, Inv3Problem::Spacing(spacing)));
    }
    let filename = matrix
        .get("filename")
        .and_then(PlistValue::as_str)
        .unwrap_or("matrix.dat");
    let raw = members
        .get(filename)
        .ok_or_else(|| CtError::inv3(path, Inv3Problem::MissingMember(filename.into())))?;
    let expected = [nx, ny, nz]
        .iter()
        .try_fold(2u64, |acc, &n| acc.checked_mul(n as u64))
        .unwrap_or(u64::MAX);
    if raw.len() as u64 != expected {
        return Err(CtError::ByteCount {
            path: path.to_owned(),
            expected,
            found: raw.len() as u64,
        });
    }
    let data = raw
        .chunks_exact(2)
        .map(|c| i16::from_le_bytes([c[0], c[1]]))
        .collect();
    let orientation = plist.get("orientation").and_then(PlistValue::as_i64);
    let source = FrameSource::Inv3 { orientation };
    Volume::new(
        nx,
        ny,
        nz,
        Spacing {
            x: spacing[0],
            y: spacing[1],
            z: spacing[2],
        },
        [0.0; 3],
        data,
    )?
    .with_frame([0.0; 3], IDENTITY_AXES, source)
}

/// The `main.plist` text for `volume` (InVesalius 3 layout, no masks or
/// surfaces).
pub fn inv3_plist(volume: &Volume, name: &str) -> String {
    let esc = name
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    let (lo, hi) = volume
        .data()
        .iter()
        .fold((i16::MAX, i16::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<!DOCTYPE plist PUBLIC \"-//Apple Computer//DTD PLIST 1.0//EN\" \"http://www.apple.com/DTDs/PropertyList-1.0.dtd\">\n\
<plist version=\"1.0\">\n<dict>\n\
\t<key>annotations</key>\n\t<dict>\n\t</dict>\n\
\t<key>format_version</key>\n\t<integer>1</integer>\n\
\t<key>masks</key>\n\t<dict>\n\t</dict>\n\
\t<key>matrix</key>\n\t<dict>\n\
\t\t<key>dtype</key>\n\t\t<string>int16</string>\n\
\t\t<key>filename</key>\n\t\t<string>matrix.dat</string>\n\
\t\t<key>shape</key>\n\t\t<array>\n\t\t\t<integer>{}</integer>\n\t\t\t<integer>{}</integer>\n\t\t\t<integer>{}</integer>\n\t\t</array>\n\
\t</dict>\n\
\t<key>modality</key>\n\t<string>CT</string>\n\
\t<key>name</key>\n\t<string>{esc}</string>\n\
\t<key>scalar_range</key>\n\t<array>\n\t\t<integer>{lo}</integer>\n\t\t<integer>{hi}</integer>\n\t</array>\n\
\t<key>spacing</key>\n\t<array>\n\t\t<real>{:?}</real>\n\t\t<real>{:?}</real>\n\t\t<real>{:?}</real>\n\t</array>\n\
\t<key>surfaces</key>\n\t<dict>\n\t</dict>\n\
</dict>\n</plist>\n",
        volume.nz, volume.ny, volume.nx, volume.spacing.x, volume.spacing.y, volume.spacing.z
    )
}

/// The bytes of an `.inv3` file holding `volume` (gzip of a tar with
/// `main.plist` and `matrix.dat`; deterministic: members have mtime 0).
pub fn inv3_bytes(volume: &Volume, name: &str) -> Vec<u8> {
    let plist = inv3_plist(volume, name);
    let mut matrix = Vec::with_capacity(volume.data().len() * 2);
    for v in volume.data() {
        matrix.extend_from_slice(&v.to_le_bytes());
    }
    let mut builder = tar::Builder::new(Vec::new());
    for (member, bytes) in [
        ("main.plist", plist.as_bytes()),
        ("matrix.dat", &matrix[..]),
    ] {
        let mut header = tar::Header::new_ustar();
        header.set_size(bytes.len() as u64);
        header.set_mode(0o644);
        header.set_mtime(0);
        header.set_entry_type(tar::EntryType::Regular);
        // Writing into a Vec cannot fail.
        builder
            .append_data(&mut header, member, bytes)
            .expect("tar into memory");
    }
    let tar_bytes = builder.into_inner().expect("tar into memory");
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    std::io::Write::write_all(&mut gz, &tar_bytes).expect("gzip into memory");
    gz.finish().expect("gzip into memory")
}

/// Writes `volume` as an `.inv3` project readable by [`read_inv3`] and by
/// InVesalius (atomically, via [`write_atomic`]).
pub fn write_inv3(path: &Path, volume: &Volume, name: &str) -> Result<(), CtError> {
    write_atomic(path, &inv3_bytes(volume, name))?;
    Ok(())
}
