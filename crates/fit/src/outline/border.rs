//! Border following on binary images (Suzuki & Abe 1985, "Topological
//! structural analysis of digitized binary images by border following",
//! CVGIP 30(1):32–46, algorithm 1).

/// A binary image, row-major with row 0 at the top (image order); `true` is
/// foreground. Foreground is 8-connected and background 4-connected, as in
/// Suzuki & Abe (1985).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BinaryImage {
    width: usize,
    height: usize,
    data: Vec<bool>,
}

impl BinaryImage {
    /// A `width × height` image from row-major `data`; `None` if the length
    /// is not `width · height`.
    pub fn new(width: usize, height: usize, data: Vec<bool>) -> Option<BinaryImage> {
        (width.checked_mul(height) == Some(data.len())).then_some(BinaryImage {
            width,
            height,
            data,
        })
    }

    /// The image whose pixel `(col, row)` is `f(col, row)`.
    pub fn from_fn(width: usize, height: usize, f: impl Fn(usize, usize) -> bool) -> BinaryImage {
        let mut data = Vec::with_capacity(width * height);
        for row in 0..height {
            for col in 0..width {
                data.push(f(col, row));
            }
        }
        BinaryImage {
            width,
            height,
            data,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Whether pixel `(col, row)` is foreground (`false` outside the image).
    pub fn get(&self, col: usize, row: usize) -> bool {
        col < self.width && row < self.height && self.data[row * self.width + col]
    }

    /// The number of foreground pixels.
    pub fn count(&self) -> usize {
        self.data.iter().filter(|&&b| b).count()
    }
}

/// Whether a border separates a foreground component from the background
/// around it (outer) or from a hole inside it (hole).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BorderKind {
    /// The outer border of an 8-connected foreground component.
    Outer,
    /// The border between a component and a 4-connected hole in it.
    Hole,
}

/// One border found by [`find_borders`]: its kind, its parent in the border
/// hierarchy and its border pixels in following order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Border {
    /// Outer or hole border.
    pub kind: BorderKind,
    /// The index of the surrounding border in the returned list (a hole's
    /// outer border, or the hole an outer border lies in); `None` for outer
    /// borders that lie in the image's background.
    pub parent: Option<usize>,
    /// The border pixels as `(col, row)`, row 0 at the top, in following
    /// order; the first pixel is not repeated at the end. A pixel can occur
    /// more than once where the component is one pixel thin.
    pub pixels: Vec<(usize, usize)>,
    /// The cracks (pixel edges between the component and the background
    /// this border faces) in following order, as `(col, row, side)` of the
    /// border pixel; each crack occurs once.
    pub cracks: Vec<(usize, usize, Side)>,
}

/// The side of a pixel on which a crack lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The edge towards column + 1.
    East,
    /// The edge towards row + 1 (down in the image).
    South,
    /// The edge towards column − 1.
    West,
    /// The edge towards row − 1 (up in the image).
    North,
}

impl Side {
    /// The crack's midpoint relative to the pixel centre, as `(dcol, drow)`
    /// in image order: `East = (½, 0)`, `South = (0, ½)` and so on.
    pub fn offset(self) -> (f64, f64) {
        match self {
            Side::East => (0.5, 0.0),
            Side::South => (0.0, 0.5),
            Side::West => (-0.5, 0.0),
            Side::North => (0.0, -0.5),
        }
    }

    /// The side facing the neighbour in direction `d` of [`DIRS`], if it is
    /// a 4-neighbour.
    fn from_dir(d: usize) -> Option<Side> {
        match d {
            0 => Some(Side::East),
            2 => Some(Side::South),
            4 => Some(Side::West),
            6 => Some(Side::North),
            _ => None,
        }
    }
}

/// Neighbour offsets `(drow, dcol)` starting east and turning clockwise on
/// the screen (row axis pointing down).
const DIRS: [(isize, isize); 8] = [
    (0, 1),
    (1, 1),
    (1, 0),
    (1, -1),
    (0, -1),
    (-1, -1),
    (-1, 0),
    (-1, 1),
];

fn dir_index(dr: isize, dc: isize) -> usize {
    DIRS.iter()
        .position(|&d| d == (dr, dc))
        .expect("neighbour offsets are within the 8-neighbourhood")
}

/// Every border of `image` by Suzuki & Abe's (1985) algorithm 1: a raster
/// scan that starts following an outer border at a pixel with a background
/// west neighbour and a hole border at a pixel with a background east
/// neighbour, follows it through the 8-neighbourhood and labels it with a
/// sequential number NBD, from which the hierarchy (Table 1) is derived.
pub fn find_borders(image: &BinaryImage) -> Vec<Border> {
    let (w, h) = (image.width, image.height);
    if w == 0 || h == 0 {
        return Vec::new();
    }
    // Labels on a one-pixel background frame: 0 background, 1 unvisited
    // foreground, ±NBD visited border pixels.
    let stride = w + 2;
    let mut f = vec![0i64; stride * (h + 2)];
    for row in 0..h {
        for col in 0..w {
            if image.data[row * w + col] {
                f[(row + 1) * stride + col + 1] = 1;
            }
        }
    }
    let at = |r: usize, c: usize| r * stride + c;
    let step = |(r, c): (usize, usize), d: usize| {
        let (dr, dc) = DIRS[d];
        (
            r.wrapping_add_signed(dr), // stays inside the frame: border pixels
            c.wrapping_add_signed(dc), // are never on the frame itself
        )
    };

    let mut borders: Vec<Border> = Vec::new();
    // NBD 1 is the frame, a hole border with no parent; border NBD k ≥ 2 is
    // borders[k − 2].
    let mut nbd: i64 = 1;
    for r in 1..=h {
        let mut lnbd: i64 = 1;
        for c in 1..=w {
            let v = f[at(r, c)];
            if v == 0 {
                continue;
            }
            let start = if v == 1 && f[at(r, c - 1)] == 0 {
                Some((BorderKind::Outer, (r, c - 1)))
            } else if v >= 1 && f[at(r, c + 1)] == 0 {
                if v > 1 {
                    lnbd = v;
                }
                Some((BorderKind::Hole, (r, c + 1)))
            } else {
                None
            };
            if let Some((kind, from)) = start {
                nbd += 1;
                // Table 1: the parent from the kind of the border LNBD.
                let (lnbd_kind, lnbd_parent, lnbd_index) = if lnbd == 1 {
                    (BorderKind::Hole, None, None)
                } else {
                    let b = &borders[(lnbd - 2) as usize];
                    (b.kind, b.parent, Some((lnbd - 2) as usize))
                };
                let parent = if kind == lnbd_kind {
                    lnbd_parent
                } else {
                    lnbd_index
                };
                let (pixels, cracks) = follow(&mut f, stride, (r, c), from, nbd, step);
                borders.push(Border {
                    kind,
                    parent,
                    pixels: pixels.into_iter().map(|(r, c)| (c - 1, r - 1)).collect(),
                    cracks: cracks
                        .into_iter()
                        .map(|((r, c), side)| (c - 1, r - 1, side))
                        .collect(),
                });
            }
            let v = f[at(r, c)];
            if v != 1 {
                lnbd = v.abs();
            }
        }
    }
    borders
}

/// The pixels `(row, col)` of a border in frame coordinates, and its cracks.
type Followed = (Vec<(usize, usize)>, Vec<((usize, usize), Side)>);

/// Step 3 of algorithm 1: follows the border that starts at `start`, coming
/// from the zero pixel `from`, labelling it with `nbd`; returns its pixels as
/// `(row, col)` in frame coordinates, and the cracks crossed by the
/// counter-clockwise sweeps of step 3.3: the zero 4-neighbours examined
/// between a pixel's predecessor and its successor.
fn follow(
    f: &mut [i64],
    stride: usize,
    start: (usize, usize),
    from: (usize, usize),
    nbd: i64,
    step: impl Fn((usize, usize), usize) -> (usize, usize),
) -> Followed {
    let at = |(r, c): (usize, usize)| r * stride + c;
    let offset = |a: (usize, usize), b: (usize, usize)| {
        dir_index(b.0 as isize - a.0 as isize, b.1 as isize - a.1 as isize)
    };
    // 3.1: clockwise from `from`, the first non-zero neighbour.
    let d0 = offset(start, from);
    let Some(p1) = (0..8)
        .map(|k| step(start, (d0 + k) % 8))
        .find(|&q| f[at(q)] != 0)
    else {
        f[at(start)] = -nbd;
        // An isolated pixel: all four cracks, in the same counter-clockwise
        // (screen) sense as the sweeps.
        let cracks = [Side::East, Side::North, Side::West, Side::South].map(|side| (start, side));
        return (vec![start], cracks.to_vec());
    };
    // 3.2
    let (mut p2, mut p3) = (p1, start);
    let mut pixels = Vec::new();
    let mut cracks = Vec::new();
    loop {
        pixels.push(p3);
        // 3.3: counter-clockwise from the element after p2.
        let mut d = offset(p3, p2);
        let mut east_zero = false;
        let p4 = loop {
            d = (d + 7) % 8;
            let q = step(p3, d);
            if f[at(q)] != 0 {
                break q;
            }
            if d == 0 {
                east_zero = true;
            }
            if let Some(side) = Side::from_dir(d) {
                cracks.push((p3, side));
            }
        };
        // 3.4
        if east_zero {
            f[at(p3)] = -nbd;
        } else if f[at(p3)] == 1 {
            f[at(p3)] = nbd;
        }
        // 3.5
        if p4 == start && p3 == p1 {
            return (pixels, cracks);
        }
        p2 = p3;
        p3 = p4;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(rows: &[&str]) -> BinaryImage {
        let h = rows.len();
        let w = rows[0].len();
        BinaryImage::from_fn(w, h, |c, r| rows[r].as_bytes()[c] == b'#')
    }

    #[test]
    fn a_rectangle_gives_its_border_pixels() {
        let img = parse(&["......", ".###..", ".###..", "......"]);
        let b = find_borders(&img);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].kind, BorderKind::Outer);
        assert_eq!(b[0].parent, None);
        let mut px = b[0].pixels.clone();
        assert_eq!(px[0], (1, 1));
        px.sort();
        assert_eq!(px, vec![(1, 1), (1, 2), (2, 1), (2, 2), (3, 1), (3, 2)]);
        // 2(w + h) distinct cracks, following the pixels.
        let cracks = &b[0].cracks;
        assert_eq!(cracks.len(), 10);
        let mut unique = cracks.clone();
        unique.sort_by_key(|&(c, r, s)| (c, r, s as u8));
        unique.dedup();
        assert_eq!(unique.len(), 10);
        assert_eq!(cracks.iter().filter(|k| k.2 == Side::North).count(), 3);
        assert_eq!(cracks.iter().filter(|k| k.2 == Side::West).count(), 2);
    }

    #[test]
    fn a_ring_gives_an_outer_border_and_its_hole() {
        let img = parse(&[".......", ".#####.", ".#...#.", ".#####.", "......."]);
        let b = find_borders(&img);
        assert_eq!(b.len(), 2);
        assert_eq!((b[0].kind, b[0].parent), (BorderKind::Outer, None));
        assert_eq!((b[1].kind, b[1].parent), (BorderKind::Hole, Some(0)));
        assert_eq!(b[0].pixels.len(), 12);
        // The hole border skips the ring's corner pixels, which touch the
        // 4-connected hole only diagonally.
        let mut hole = b[1].pixels.clone();
        hole.sort();
        assert_eq!(
            hole,
            vec![
                (1, 2),
                (2, 1),
                (2, 3),
                (3, 1),
                (3, 3),
                (4, 1),
                (4, 3),
                (5, 2)
            ]
        );
    }

    #[test]
    fn a_component_inside_a_hole_has_the_hole_as_parent() {
        let img = parse(&[
            "#########",
            "#.......#",
            "#..###..#",
            "#..###..#",
            "#.......#",
            "#########",
        ]);
        let b = find_borders(&img);
        assert_eq!(b.len(), 3);
        assert_eq!((b[0].kind, b[0].parent), (BorderKind::Outer, None));
        assert_eq!((b[1].kind, b[1].parent), (BorderKind::Hole, Some(0)));
        assert_eq!((b[2].kind, b[2].parent), (BorderKind::Outer, Some(1)));
    }

    #[test]
    fn single_pixels_and_thin_lines() {
        let img = parse(&["#.#", "...", "###"]);
        let b = find_borders(&img);
        assert_eq!(b.len(), 3);
        assert_eq!(b[0].pixels, vec![(0, 0)]);
        assert_eq!(b[0].cracks.len(), 4);
        assert_eq!(b[1].pixels, vec![(2, 0)]);
        // A one-pixel-thin line is followed there and back.
        assert_eq!(b[2].pixels, vec![(0, 2), (1, 2), (2, 2), (1, 2)]);
        // ... and each of its 8 cracks is crossed once.
        assert_eq!(b[2].cracks.len(), 8);
        assert!(find_borders(&BinaryImage::from_fn(0, 0, |_, _| true)).is_empty());
        // Pixels touching the image edge.
        let full = BinaryImage::from_fn(2, 2, |_, _| true);
        assert_eq!(find_borders(&full)[0].pixels.len(), 4);
    }
}
