//! Records' determinant signs from their own factorisation
//! ([`super::Options::overlap_records`]), on a second thread or not
//! ([`super::Options::overlap_thread`]).
//!
//! A Newton step's cost on a wide Jacobian (a charged rod's plectoneme) is
//! its corrections — block eliminations on a supernodal LU, ~22 ms at 5–12
//! turns of the 1 kbp DNA scene — and its record's sign det B, which needs
//! B's own simplicial LU (~75 ms: faer's supernodal factors do not give
//! U's diagonal). The sign is needed by nothing the next step does, so it
//! can be taken on a second thread from a copy of B while the next step
//! is predicted and corrected, and the record is told once both are done.
//!
//! The numbers do not depend on the thread: the point is factorised for
//! solves (its tangent) and the signs come from B's simplicial LU of the
//! same values, in the same column order, either way; only where that LU
//! runs differs. So a run gives the same records, bitwise, with or
//! without the second thread (c-api.md: results bitwise identical for
//! any thread count), and one thread costs the wall clock of both.
//! Where the point's own factorisation is B's simplicial LU already (a
//! pattern too narrow for block elimination), the signs are read off it
//! at once, on any thread count: no second factorisation.

use super::tangent::Bordered;
use super::{Counts, Record};
use crate::error::Result;
use crate::linalg::sparse::ColumnOrder;
use crate::linalg::SparseLu;
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// What the second thread hands back: its LU and copy of B (kept for the
/// next record on this pattern), sign det B and the negative pivots
/// ((0, 0) if B is singular, as [`Bordered::determinant_signs`] reports),
/// and the time taken.
struct Signed {
    lu: SparseLu,
    values: Vec<f64>,
    sign: f64,
    pivots: usize,
    time: Duration,
}

/// A record whose signs are being taken.
struct Waiting {
    record: Record,
    /// sign(t_Λ ⟨v, t⟩_W), 0 when t_Λ = 0 ([`Bordered::orientation`]):
    /// sign det R_x = sign det B times this.
    orientation: f64,
    signs: Signs,
}

/// Where they are taken: on the second thread, or (one thread, or no
/// thread could be started) already here, or read off the point's own
/// factorisation (sign det B, negative pivots).
enum Signs {
    Thread(JoinHandle<Signed>),
    Here(Box<Signed>),
    InHand(f64, usize),
}

/// B's simplicial LU of `values` with `lu`: its signs and pivots.
fn signed(mut lu: SparseLu, values: Vec<f64>) -> Signed {
    let t = Instant::now();
    let (sign, pivots) = match lu.factorise_exact(&values) {
        Ok(()) => (lu.determinant_sign_and_log().0, lu.negative_pivots()),
        Err(_) => (0.0, 0),
    };
    Signed { lu, values, sign, pivots, time: t.elapsed() }
}

/// At most one record waiting at a time.
#[derive(Default)]
pub(crate) struct Overlap {
    spare: Option<(SparseLu, Vec<f64>)>,
    waiting: Option<Waiting>,
}

impl Overlap {
    /// Take the signs of `record` — B the bordered tangent just evaluated
    /// at its point — off its factorisation when that is B's simplicial
    /// LU ([`Bordered::signs_in_hand`]), else from B's own simplicial LU on
    /// a second thread when `thread` (here, if not, or if the system
    /// refuses a thread: the same LU in the same column order, so the
    /// same numbers). Any record still waiting must have been
    /// [`Overlap::finish`]ed. Returns the record as it waits (signs 0, no
    /// pivots).
    pub fn start(
        &mut self,
        bordered: &mut Bordered,
        record: Record,
        orientation: f64,
        thread: bool,
    ) -> Result<&Record> {
        debug_assert!(self.waiting.is_none(), "a record is still waiting");
        if bordered.signs_in_hand() {
            let signs = Signs::InHand(bordered.determinant_sign(), bordered.negative_pivots());
            return Ok(&self.waiting.insert(Waiting { record, orientation, signs }).record);
        }
        let (lu, mut values) = match self.spare.take() {
            Some(kept) => kept,
            None => (bordered.exact_twin()?, Vec::new()),
        };
        values.clear();
        values.extend_from_slice(bordered.values());
        let signs = if thread {
            // The thread takes the LU from a shared slot; should the spawn
            // fail, the closure is dropped unrun and the LU is taken back.
            let job = Arc::new(Mutex::new(Some((lu, values))));
            let theirs = Arc::clone(&job);
            let spawned = std::thread::Builder::new().name("rodkit-record-signs".into()).spawn(move || {
                let (lu, values) = theirs.lock().unwrap_or_else(PoisonError::into_inner).take().expect("the job");
                signed(lu, values)
            });
            match spawned {
                Ok(handle) => Signs::Thread(handle),
                Err(_) => {
                    let taken = job.lock().unwrap_or_else(PoisonError::into_inner).take();
                    let (lu, values) = match taken {
                        Some(job) => job,
                        None => (bordered.exact_twin()?, bordered.values().to_vec()),
                    };
                    Signs::Here(Box::new(signed(lu, values)))
                }
            }
        } else {
            Signs::Here(Box::new(signed(lu, values)))
        };
        Ok(&self.waiting.insert(Waiting { record, orientation, signs }).record)
    }

    /// The column order of the factorisations taken for the records (None
    /// before the first).
    pub fn column_order(&self) -> Option<ColumnOrder> {
        self.spare.as_ref().filter(|(lu, _)| lu.factorisations > 0).map(|(lu, _)| lu.column_order())
    }

    /// The waiting record with its signs (None if none waits). Its
    /// factorisation is counted, its time in `times.overlapped` (on this
    /// thread too: part of the wall clock then).
    pub fn finish(&mut self, counts: &mut Counts) -> Option<Record> {
        let Waiting { mut record, orientation, signs } = self.waiting.take()?;
        let joined = match signs {
            Signs::Thread(handle) => handle.join(),
            Signs::Here(signed) => Ok(*signed),
            Signs::InHand(sign, pivots) => {
                set_signs(&mut record, sign, orientation, Some(pivots));
                return Some(record);
            }
        };
        match joined {
            Ok(signed) => {
                counts.factorisations += 1;
                counts.times.overlapped += signed.time;
                set_signs(&mut record, signed.sign, orientation, Some(signed.pivots));
                self.spare = Some((signed.lu, signed.values));
            }
            // The thread panicked (a bug): the record says its signs are
            // unknown rather than taking the host down.
            Err(_) => set_signs(&mut record, 0.0, 0.0, None),
        }
        Some(record)
    }
}

/// sign det B, sign det R_x = sign det B × the orientation (0 when that
/// is 0), and the negative pivots into `record`.
fn set_signs(record: &mut Record, sign: f64, orientation: f64, pivots: Option<usize>) {
    record.bordered_det_sign = sign;
    record.det_sign = if orientation == 0.0 { 0.0 } else { sign * orientation };
    record.negative_pivots = pivots;
}

/// A record still waiting when the run unwinds (a panicking callback):
/// its thread is joined (one factorisation at most), not left running
/// past the call.
impl Drop for Overlap {
    fn drop(&mut self) {
        if let Some(Waiting { signs: Signs::Thread(handle), .. }) = self.waiting.take() {
            let _ = handle.join();
        }
    }
}
