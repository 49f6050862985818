//! Samples of the window's planes read without a look at their type per
//! sample: the gradient code is generic over [`Samples`], and
//! [`with_planes`] picks the instance once per layer.

use super::window::Plane;
use crate::volume::LentPlane;

/// A plane of samples the gradient can read.
pub trait Samples: Copy {
    /// Whether a sample can be NaN (integers cannot).
    const MAY_BE_NAN: bool;

    /// A sample as the differences take it: a wider integer for integer
    /// samples (so a difference is one integer subtraction and one
    /// conversion), `f64` otherwise.
    type Wide: Copy;

    /// Sample `i` as an `f64`, NaN as it is.
    fn raw(self, i: usize) -> f64;

    /// Samples `start..start + N` as [`Wide`](Self::Wide) values, with one
    /// bounds check.
    fn wide<const N: usize>(self, start: usize) -> [Self::Wide; N];

    /// A run of samples cut from a plane by [`sub`](Self::sub).
    type Run: Copy;

    /// Samples `start..end` (one bounds check for the cut).
    fn sub(self, start: usize, end: usize) -> Self::Run;

    /// Sample `j` of `run` as a [`Wide`](Self::Wide) value.
    fn at(run: Self::Run, j: usize) -> Self::Wide;

    /// `a - b` as an `f64`: the same bits as `raw` of each subtracted
    /// (exact for integers, whose differences `f64` holds).
    fn minus(a: Self::Wide, b: Self::Wide) -> f64;

    /// Samples `start..start + N` as `f64`, NaN as they are: what `N`
    /// calls of [`raw`](Self::raw) give, with one bounds check for a
    /// typed slice instead of `N`.
    #[inline(always)]
    fn run<const N: usize>(self, start: usize) -> [f64; N] {
        std::array::from_fn(|j| self.raw(start + j))
    }

    /// Sample `i` as an `f64`, NaN as `tie` (NaN is outside, a tie at the
    /// isovalue, as in the extraction: so a difference across a NaN sample,
    /// such as the border `Padded` adds for `--close`, stays finite).
    #[inline(always)]
    fn value(self, i: usize, tie: f64) -> f64 {
        let v = self.raw(i);
        if Self::MAY_BE_NAN && v.is_nan() {
            tie
        } else {
            v
        }
    }
}

/// Slices of samples of one type, exact as `f64`; NaN only for floats;
/// differences taken in `$wide`.
macro_rules! typed_samples {
    ($may_be_nan:expr, $wide:ty => $($t:ty),*) => {
        $(impl Samples for &[$t] {
            const MAY_BE_NAN: bool = $may_be_nan;
            type Wide = $wide;

            #[inline(always)]
            fn wide<const N: usize>(self, start: usize) -> [$wide; N] {
                let run: &[$t; N] = self[start..start + N]
                    .try_into()
                    .expect("a range of N samples");
                std::array::from_fn(|j| <$wide>::from(run[j]))
            }

            type Run = Self;

            #[inline(always)]
            fn sub(self, start: usize, end: usize) -> Self {
                &self[start..end]
            }

            #[inline(always)]
            fn at(run: Self, j: usize) -> $wide {
                <$wide>::from(run[j])
            }

            #[inline(always)]
            fn minus(a: $wide, b: $wide) -> f64 {
                (a - b) as f64
            }

            #[inline(always)]
            fn raw(self, i: usize) -> f64 {
                f64::from(self[i])
            }

            #[inline(always)]
            fn run<const N: usize>(self, start: usize) -> [f64; N] {
                let run: &[$t; N] = self[start..start + N]
                    .try_into()
                    .expect("a range of N samples");
                std::array::from_fn(|j| f64::from(run[j]))
            }
        })*
    };
}

typed_samples!(false, i32 => u8, i8, u16, i16);
typed_samples!(false, i64 => u32, i32);
typed_samples!(true, f64 => f32, f64);

/// Any plane, its type looked at per sample: for a layer whose planes are
/// not all of one type (a source that lends some planes and not others).
impl Samples for Plane<'_> {
    const MAY_BE_NAN: bool = true;
    type Wide = f64;

    #[inline(always)]
    fn wide<const N: usize>(self, start: usize) -> [f64; N] {
        self.run(start)
    }

    /// The plane and where the run starts (reads are checked one by one).
    type Run = (Self, usize);

    #[inline(always)]
    fn sub(self, start: usize, _end: usize) -> (Self, usize) {
        (self, start)
    }

    #[inline(always)]
    fn at((plane, start): (Self, usize), j: usize) -> f64 {
        plane.raw(start + j)
    }

    #[inline(always)]
    fn minus(a: f64, b: f64) -> f64 {
        a - b
    }

    #[inline(always)]
    fn raw(self, i: usize) -> f64 {
        match self {
            Plane::Lent(lent) => lent.get(i),
            Plane::Read(s) => s[i],
        }
    }
}

/// Work on a layer's four planes, whatever their sample type.
pub trait Visit {
    /// What the work gives.
    type Output;

    /// Does the work on `planes` (in the order of
    /// [`Window::around`](super::window::Window::around)).
    fn visit<P: Samples>(self, planes: [P; 4]) -> Self::Output;
}

/// Hands `planes` to `visit` as slices of their own sample type when all
/// four have the same (planes read into `f64` count as lent `f64` ones),
/// so that the work is compiled once per type and looks at no type per
/// sample; as [`Plane`]s otherwise.
pub fn with_planes<V: Visit>(planes: [Plane<'_>; 4], visit: V) -> V::Output {
    /// Visits the planes as `&[T]` if a `$pattern` binds `$s` in all four.
    macro_rules! uniform {
        ($s:ident in $($pattern:pat),*) => {
            $(if let [Some(a), Some(b), Some(c), Some(d)] = planes.map(|p| match p {
                $pattern => Some($s),
                _ => None,
            }) {
                return visit.visit([a, b, c, d]);
            })*
        };
    }
    uniform!(
        s in Plane::Lent(LentPlane::F64(s)) | Plane::Read(s),
        Plane::Lent(LentPlane::U8(s)),
        Plane::Lent(LentPlane::I8(s)),
        Plane::Lent(LentPlane::U16(s)),
        Plane::Lent(LentPlane::I16(s)),
        Plane::Lent(LentPlane::U32(s)),
        Plane::Lent(LentPlane::I32(s)),
        Plane::Lent(LentPlane::F32(s))
    );
    visit.visit(planes)
}
