"""Diagnosis: what the rigid model gets wrong, its physical cause, and the gain of extending
it.

This docstring is the one description of the procedure; each step lives in its own module
(named in its heading), and :func:`volumetric.diagnose.diagnosis.diagnose` runs them in
order.

Procedure (``ednc diagnose``):

1. **Base model** (:mod:`~volumetric.diagnose.base`). The model ``ednc fit`` gives by
   default (:func:`volumetric.identify.fit.fit`: 21 errors, smooth polynomial components on
   every linear axis and on a rotary axis of short travel, harmonics up to 4 per turn on
   every rotary axis of at least half a turn, degrees and orders by BIC) is identified on
   the readings; its column set (degrees, identifiable parameters) and weights are then kept
   fixed. An effect is what the readings show beyond that model: a rotary table's once- and
   twice-per-turn error motions are the base's, never an effect. When effects are named
   (steps 4-6), the degrees are chosen again on the readings with those effects taken out
   and the whole diagnosis runs again on that base, up to ``REFITS`` times
   (:func:`~volumetric.diagnose.base.base_without`): with a 12 µm backlash in the readings,
   BIC takes a cubic straightness for noise, and what the too-smooth base leaves decides
   between sensors that follow the same shop air.
2. **Held-out readings** (:mod:`~volumetric.diagnose.splits`), the split chosen from the
   data alone, the same way every time (the JSON's ``split``):

   * ``forward`` when the readings are time-ordered (every test spans at least
     ``TIME_ORDERED_SPAN`` of the campaign,
     :func:`~volumetric.diagnose.splits.time_ordered`: a thermal test, a long-term run):
     ``FORWARD_BLOCKS`` contiguous blocks of equal counts in time; each block from
     ``FIRST_JUDGED`` on is predicted by a model fitted on all blocks before it, never on
     anything later. ``blocks`` reports each judged block, their mean and the worst;
   * ``runs`` otherwise, in ``K = 5`` folds: a test with several runs gives whole runs to a
     fold (so repeated readings of one point never sit on both sides, and a time-dependent
     effect shows as a run that disagrees with the others); a test with one run gives
     contiguous stretches of it;
   * ``chronological`` with ``holdout_after`` (expert option): fit before, judge after.

   In every split, a lagged thermal model's (:mod:`~volumetric.diagnose.lagged`) sensors and
   time constants are selected again in every fold from that fold's training readings
   (``Candidate.per_fold``), wherever it is judged: alone, with further effects beside it,
   or when those are chosen again. Selected once on every reading, only its coefficients
   refitted per fold, it would carry the held-out readings' shape into their prediction. (A
   lagged model that does not beat the best candidate even judged that way, which favours
   it, is dropped unjudged: it could only matter as the best.)
3. **Candidates** (:mod:`volumetric.diagnose.candidates`), each a few extra columns of the
   same least-squares problem, all along one machine axis ``k`` (``u_k`` is what the reading
   senses of 1 µm along axis k's own line of motion,
   :func:`~volumetric.diagnose.candidates.along_axes`: its component along k, turned by the
   rotary axes between the reading's frame and the axis, as on an R-test of a rotary table):

   ===================  =========================================  ======================
   effect               extra column(s)                            estimate
   ===================  =========================================  ======================
   thermal_expansion    ``u_k (T_s − T̄_s)(q_k − q_min) / 1000``    α, ``um_per_m_K``
   thermal_drift        ``u_k (T_s − T̄_s)``; refined by lagged      k, ``um_per_K``
                        temperatures: the selection, averaged
                        with an all-sensor part (its prediction
                        as it comes, ``Candidate.fixed``) when
                        a map can carry the
                        model's records (``MAP_THERMAL_RECORDS``;
                        :mod:`volumetric.identify.thermal`, its
                        step 6)
   backlash             ``−u_k d_k / 2`` (d_k approach direction)  B, ``reversal_um``
   periodic             ``u_k sin(2π q_k/P)``, ``u_k cos(2π q_k/P)``  A, P
                        with P from the base residual's spectrum
   time_drift           ``u_k (t − t̄) / 3600``                     ``um_per_h``
   rotary_periodic      per rotary axis of >= 180° travel: the     ``order``,
                        harmonic of order N (cos, sin) on each of  ``radial_um``,
                        its six components, N from 5 to what the   ``angular_urad`` (with
                        finest R-test's angular step resolves      ``_std``), every
                        (``order_limit``), by a periodogram of     component's amplitude
                        the base residual beside the base
                        (:mod:`~volumetric.diagnose.rotary`)
   rotary_backlash      per rotary axis whose direction the        B, ``reversal_urad``
                        readings give (``dir_<axis>``): −s d / 2,
                        s what the reading senses of 1 µrad of
                        the axis's own angle
   ===================  =========================================  ======================

4. **Ranking and significance** (:mod:`~volumetric.diagnose.gates`). Candidates are ranked
   by held-out RMS of the displacement readings. The best (and only the best) is named when
   its gain is significant: it must reduce the held-out RMS of all displacement readings by
   at least ``MIN_GAIN``; over the readings it touches, the held-out squared errors of base
   and candidate, compared in contiguous chunks (so that correlated neighbours count once),
   must show a mean gain of ``Z_MIN`` standard errors; and its coefficient must stand
   ``T_MIN`` standard uncertainties clear of zero (a cyclic error's dozen coefficients, some
   nearly collinear on a given set of balls: the square root of their Wald statistic per
   coefficient). Otherwise the answer is ``none``: a false
   alarm on clean data is as wrong as a miss. On clean simulated campaigns the best spurious
   candidate gains well under 1 %; a real effect of the smallest realistic size gains tens
   of per cent. Sensors whose temperatures move together cannot be told apart by any data:
   the runners-up of the same effect and axis within ``TIE`` of the best are listed as
   ``alternatives``. On a forward split, the model saved for a thermal drift named by its
   static candidate is chosen on future splits (each fitted before a judged block and
   judged on every later one, :mod:`~volumetric.diagnose.choice`): the static drift or
   its lagged refinement, the plain least squares on every sensor when that predicts
   better on average, a richer model on every sensor only when it predicts better in
   every future split and by ``RICHER_MARGIN`` on average.
5. **Estimate** (:mod:`~volumetric.diagnose.estimate`; a lagged drift's in
   :mod:`~volumetric.diagnose.lagged`). The named effect is fitted together with the base
   model on all readings; its coefficient and standard uncertainty are reported in physical
   units, and it becomes a term of the machine's
   :class:`~volumetric.model.model.MachineModel` (a lagged thermal drift as a
   ``thermal_dynamic`` term with its time constants and end states, every term of the
   average with the coefficient and block-jackknife uncertainty of its own fit, only the
   rigid part fitted beside it; the fit's tool-tip offsets in ``info["offsets_um"]``), so
   that the saved model applied forward (``ednc predict``) reproduces the figure. Its
   estimate's ``dynamic`` gives ``steady_um_per_K``: what each sensor 1 K off moves the
   drift by at steady state (sensors that move together can carry large coefficients of
   opposite signs; the largest is what a faulty sensor would cost).
6. **Further effects** (``effects``, :mod:`~volumetric.diagnose.further`): forward
   selection. With the effects found so far in the model, every candidate of another effect
   or axis is judged again against that model's held-out residuals and the best is added
   when it passes the same three tests (``MIN_GAIN`` of the remaining RMS, ``Z_MIN``,
   ``T_MIN``), up to ``MAX_EFFECTS``. A null campaign cannot pass: the gates are those that
   keep single effects free of false alarms. Each entry's ``rms_after_um`` counts the
   effects up to it; the top-level ``rms_after_um`` is the last one's. A cyclic error of a
   rotary axis adds its harmonic to the saved model's components of that axis (one
   ``rotary_periodic`` per rotary axis at most, A and C independently). When two or more
   effects are named, each thermal or time effect is chosen again among the thermal and time
   candidates of its axis with every other effect in the model
   (:func:`~volumetric.diagnose.further.refine`): forward selection picked it while another
   effect on that axis still distorted the comparison of sensors that move alike. A time
   drift gives way to a thermal candidate of its axis within ``TIME_TIE``
   (:func:`~volumetric.diagnose.gates.prefer_physical`). Each named thermal effect lists in
   its entry the ``alternatives``: sensors of its effect and axis within ``TIE`` of it with
   every other named effect in the model
   (:func:`~volumetric.diagnose.further.list_alternatives`). A drift and an expansion of
   one axis share variance (the expansion's mean over positions is a drift of its sensor):
   every pair of them on an axis that holds either is judged with both in the model
   (:mod:`~volumetric.diagnose.joint`); the best (a pair on two sensors unless one on a
   single sensor, one body's growth about another fixed point, beats them all by more
   than ``TIE``: :func:`~volumetric.diagnose.joint.best_pair`) replaces the axis's
   thermal effects (a lagged drift included) when it beats them and its weaker member
   passes the gates against the best single one (its gain over the readings of the
   axis), and both are estimated in one fit, each entry giving ``correlation``: the
   other's effect, axis, sensor and ``r``, the correlation of the two estimates.
7. **Unexplained structure** (:mod:`volumetric.diagnose.unexplained`): the final held-out
   residuals are searched for what they still follow (position, a period along an axis,
   approach direction, time, a temperature). Structure there is reported as an
   ``unexplained`` entry of ``effects`` (``estimate``: ``correlates_with``, the strongest
   correlate, ``structure_um``, every ``correlates`` with its F-test figures). A named
   effect whose own correlate (its sensor; its axis's position for a periodic error or an
   expansion; its axis's direction for a backlash) still carries structure of at least
   ``DEMOTE_RATIO`` of what the effect explained was the nearest candidate, not the cause:
   it moves into the entry's ``nearest`` list and the ``unexplained`` entry takes its place
   (the top-level ``effect`` when it was the first). The saved model keeps every term
   selected (each made a held-out gain). A periodic error's period is found again, in
   :func:`~volumetric.diagnose.further.refine`, from the residual of the model with the
   other effects in.

Candidates that the data cannot support are not guessed at: they are listed in
``not_assessed`` with the reason (no temperature columns, one approach direction only, an
axis never sensed)."""
