"""The built-in parts: figures read from public datasheets (or public pages quoting them, named).

Only parts whose angle random walk (or noise density) could be read from a public source
are included, and, but for the high-range MEMS part (whose sheet prints none), their in-run
bias stability; a figure the source does not give is left None, never filled in. Where the
source also prints the IMU's accelerometers, their figures are the ``accel_*`` fields (read
from the same source, and said so in ``notes``).
``source`` names the document and revision; where the figures were read from a page quoting
the datasheet, that page is named too.
"""

from __future__ import annotations

from gyrobench.sim.parts._part import Datasheet

__all__ = ["CATALOGUE"]

_NAVTK = "NavToolkit (is4s.github.io/NavToolkit) ImuModel documentation, which quotes the sheet"

_G0 = 9.80665  # m/s^2 per g (standard gravity, the g of every sheet's mg and ug)
_FT = 0.3048  # m per international foot (NavToolkit's hg1700_model converts with it)

CATALOGUE: tuple[Datasheet, ...] = (
    Datasheet(
        name="stim300",
        source_kind="secondary",
        manufacturer="Safran Sensing Technologies (Sensonor)",
        model="STIM300",
        technology="MEMS",
        grade="tactical",
        source=f"STIM300 datasheet TS1524 rev. 9 (figures as quoted in {_NAVTK}, stim300_model)",
        range_dps=400.0,
        bias_instability_dph=0.5,
        arw=0.15,
        scale_factor_repeatability=500.0,
        g_sensitivity=1.0,
        accel_vrw_m_s_sqrt_h=0.06,
        accel_bias_instability_ug=50.0,
        accel_scale_factor_repeatability_ppm=300.0,
        notes=(
            "range: the sheet's non-linearity is given up to 400 deg/s; scale-factor 500 ppm is the sheet's "
            "accuracy, taken as the 1 sigma; bias range +-250 deg/h is a limit, not a repeatability, so "
            "no turn-on bias is drawn; Sensonor measures bias instability as the ADEV minimum over 18 h at "
            "1000 Hz (sensonor.com FAQ); accelerometers from the same NavToolkit model: VRW 0.06 m/s/sqrt(h), "
            "bias 0.05 mg (its 1 h Gauss-Markov sigma, read as the in-run stability), scale factor 300 ppm "
            "(1 sigma); its initial accelerometer bias sigma 0.75 mg is a filter's starting uncertainty, not "
            "drawn (as its gyro one is not); range not given (the part comes in several g ranges): unset"
        ),
    ),
    Datasheet(
        name="hg1700",
        source_kind="secondary",
        manufacturer="Honeywell",
        model="HG1700",
        technology="RLG",
        grade="tactical",
        source=f"Honeywell HG1700 IMU brochure N61-1619-000-001 (figures as quoted in {_NAVTK}, hg1700_model)",
        bias_instability_dph=1.0,
        arw=0.125,
        accel_vrw_m_s_sqrt_h=0.065 * _FT,
        accel_bias_instability_ug=1000.0,
        notes=(
            "range: not in the quoting page, left unset (no saturation); "
            "gyro bias 1 deg/h (1 sigma) read as the in-run stability figure; accelerometers from the same "
            "model: VRW 0.065 ft/s/sqrt(h) (0.0198 m/s/sqrt(h)), bias 9.81e-3 m/s^2 = 1 mg (1 sigma) read as "
            "the in-run stability as the gyro's is; at that bias the white noise lies below the flicker floor "
            "above about 1 ms (crossover (N/(0.664 B))^2 = 1.1 ms)"
        ),
    ),
    Datasheet(
        name="hg9900",
        source_kind="secondary",
        manufacturer="Honeywell",
        model="HG9900 (GG1320 RLGs)",
        technology="RLG",
        grade="navigation",
        source=f"Honeywell HG9900 IMU brochure N61-1638-000-000 (figures as quoted in {_NAVTK}, hg9900_model)",
        bias_instability_dph=0.0035,
        arw=0.002,
        scale_factor_repeatability=5.0,
        accel_bias_instability_ug=25.0,
        accel_scale_factor_repeatability_ppm=100.0,
        notes=(
            "ARW 0.002 deg/sqrt(h) is the brochure's maximum; gyro bias 0.0035 deg/h (1 sigma) read as the "
            "in-run stability figure; range not in the quoting page, left unset; accelerometers from the same "
            "model: bias 25 ug (25 x 9.81e-6 m/s^2) read as the in-run stability, scale factor 100 ppm (1 sigma); "
            "its accelerometer random walk 1e-12 m/s^(3/2) is a numerical placeholder, not a figure: no VRW is "
            "drawn"
        ),
    ),
    Datasheet(
        name="openrtk330",
        source_kind="primary",
        manufacturer="Aceinna",
        model="OpenRTK330 IMU",
        technology="MEMS",
        grade="industrial",
        source=(
            "Aceinna OpenRTK330 documentation, 'IMU Sensors' "
            "(github.com/Aceinna/docs_openrtk, 300ZA/imu-sensors.rst)"
        ),
        range_dps=400.0,
        bias_instability_dph=6.0,
        arw=0.3,
        scale_factor_repeatability=1000.0,
        bandwidth=50.0,
        resolution=0.02,
        accel_range_g=8.0,
        accel_bias_instability_ug=20.0,
        accel_vrw_m_s_sqrt_h=0.05,
        accel_scale_factor_repeatability_ppm=1000.0,
        accel_bandwidth_hz=50.0,
        accel_resolution_mg=0.5,
        notes=(
            "all figures are the page's limits (<): range > 400, bias instability < 6 deg/h (Allan curve, "
            "1 sigma), ARW < 0.3, resolution < 0.02 deg/s, scale-factor accuracy < 0.1 %, bandwidth 5-50 Hz "
            "(the upper end taken); the page's accelerometer table likewise: range > 8 g, bias instability "
            "< 20 ug (Allan curve, 1 sigma), VRW < 0.05 m/s/sqrt(h), resolution < 0.5 mg, scale-factor accuracy "
            "< 0.1 % (1000 ppm, taken as the 1 sigma), bandwidth 5-50 Hz (50 taken); its bias stability over "
            "temperature < 5 mg (RMS over temperature) is not a coefficient per kelvin: unset"
        ),
    ),
    Datasheet(
        name="adxrs646",
        source_kind="primary",
        manufacturer="Analog Devices",
        model="ADXRS646",
        technology="MEMS",
        grade="industrial",
        source="ADXRS646 data sheet (Analog Devices; revision not shown in the copy read, manualmachine.com)",
        range_dps=250.0,
        bias_instability_dph=12.0,
        arw=0.01 * 60.0,
        notes="ARW 0.01 deg/sqrt(s) = 0.6 deg/sqrt(h); bias drift 12 deg/h typical; range: +-250 deg/s minimum",
    ),
    Datasheet(
        name="mti-1",
        source_kind="secondary",
        manufacturer="Xsens",
        model="MTi-1",
        technology="MEMS",
        grade="consumer",
        source=(
            "Xsens MTi-1 gyroscope figures as tabulated in 'Characteristics of IMU Xsens MTI-1 sensors', "
            "Transactions on Aerospace Research, doi:10.2478/tar-2023-0022 (datasheet revision not given)"
        ),
        range_dps=2000.0,
        bias_instability_dph=10.0,
        noise_density=0.007,
        noise_density_sided="two",
        bandwidth=255.0,
        accel_range_g=16.0,
        accel_bias_instability_ug=30.0,
        accel_noise_density_ug=120.0,
        accel_bandwidth_hz=324.0,
        notes=(
            "noise density 0.007 deg/s/sqrt(Hz); the table does not state the PSD convention: taken two-sided "
            "(ARW = 60 x density, the convention of ADI and Xsens ARW figures); the same table's accelerometer "
            "block: range +-16 g, zero-offset instability 0.03 mg (read as the ADEV minimum), noise density "
            "120 ug/sqrt(Hz) (two-sided, as the gyro's), bandwidth 324 Hz on x and y (262 Hz on z: one "
            "bandwidth per triad is modelled, the x/y one)"
        ),
    ),
    Datasheet(
        name="ahrs380",
        source_kind="secondary",
        manufacturer="MEMSIC (Aceinna)",
        model="AHRS380SA",
        technology="MEMS",
        grade="industrial",
        source=(
            "MEMSIC AHRS380SA datasheet (figures as used in gnss-ins-sim's imu_model.py low-accuracy profile, "
            "which cites it; revision not given)"
        ),
        bias_instability_dph=10.0,
        arw=0.75,
        accel_vrw_m_s_sqrt_h=0.05,
        accel_bias_instability_ug=2.0e-4 / _G0 * 1e6,
        notes=(
            "range not in the quoting source: left unset (no saturation); accelerometers from the same "
            "profile (accel_low_accuracy): VRW 0.05 m/s/sqrt(h), bias instability 2.0e-4 m/s^2 (20.4 ug, "
            "its 'b_drift', which gnss-ins-sim documents as the bias instability), its turn-on bias 0"
        ),
    ),
    Datasheet(
        name="sch16t-k01",
        source_kind="primary",
        manufacturer="Murata",
        model="SCH16T-K01",
        technology="MEMS",
        grade="industrial",
        source=(
            "Murata SCH16T-K01 data sheet, Doc.No. 11624 Rev. 2 (January 2024), Table 4 'Performance "
            "specifications for gyroscope' and Table 6 'Performance specifications for accelerometer' (read "
            "from a public chunked copy, github.com/taylor-curran/data-sheets-naive-chunking)"
        ),
        range_dps=300.0,
        bias_instability_dph=0.5,
        bias_instability_is_b=True,
        arw=0.015,
        noise_density=0.0006,
        bias_repeatability=0.6 / 3 * 3600.0,
        g_sensitivity=0.006 * _G0 * 3600.0,
        resolution=1.0 / 1600.0,
        accel_range_g=80.0 / _G0,
        accel_bias_instability_ug=0.20e-3 / _G0 * 1e6,
        accel_vrw_m_s_sqrt_h=0.030,
        accel_noise_density_ug=0.8e-3 / _G0 * 1e6,
        accel_bias_repeatability_mg=0.14 / 3 / _G0 * 1e3,
        accel_resolution_mg=1.0 / 3200.0 / _G0 * 1e3,
        notes=(
            "range: guaranteed +-300 deg/s at the lowest sensitivity; bias instability 0.5 deg/h is defined by "
            "the sheet as the Allan minimum / 0.664, i.e. B itself; ARW 0.015 deg/sqrt(h) is used (the sheet's "
            "noise density 0.0006 deg/s/sqrt(Hz) is recorded, not used); bias repeatability: offset +-0.6 deg/s "
            "at +-3 sigma over -40..110 degC, so 0.2 deg/s 1 sigma (it includes temperature); g-sensitivity "
            "0.006 (deg/s)/(m/s^2) for a DC gravity input; resolution: 1600 LSB/(deg/s) in 20-bit mode; "
            "accelerometers from Table 6 'Performance specifications for accelerometer' of the same sheet: "
            "range +-80 m/s^2 at the lowest sensitivity, bias instability 0.20 mm/s^2 (the Allan minimum / "
            "0.664, B itself, as the gyro's), VRW 30 (mm/s)/sqrt(h) (used; the noise density 0.8 "
            "(mm/s^2)/sqrt(Hz) is recorded, not used), offset +-0.14 m/s^2 at +-3 sigma over -40..110 degC "
            "(so 0.047 m/s^2 1 sigma), resolution 3200 LSB/(m/s^2) in 20-bit mode; the offset and sensitivity "
            "drifts over temperature are half-ranges over a sweep, not coefficients per kelvin: unset"
        ),
    ),
    Datasheet(
        name="adis16495-1",
        source_kind="primary",
        manufacturer="Analog Devices",
        model="ADIS16495-1",
        technology="MEMS",
        grade="tactical",
        source=(
            "ADIS16495 data sheet Rev. C (Analog Devices, 2017-2020), Features list "
            "(read from the copy at pdf.datasheet.live, ADIS16495-3BMLZ)"
        ),
        range_dps=125.0,
        bias_instability_dph=0.8,
        arw=0.09,
        accel_range_g=8.0,
        accel_bias_instability_ug=3.2,
        notes=(
            "the -1 range option (+-125 deg/s) is the one the 0.8 deg/h in-run bias stability and 0.09 "
            "deg/sqrt(h) ARW are quoted for; ADI defines in-run bias stability as the Allan-deviation minimum; "
            "repeatability, temperature coefficients and resolution were not in the part read: left unset; "
            "accelerometers from the same Features list: +-8 g, 3.2 ug in-run bias stability; their VRW is not "
            "in the part read: no white acceleration noise is drawn"
        ),
    ),
    Datasheet(
        name="dsp-1760",
        source_kind="secondary",
        manufacturer="KVH Industries (now EMCORE)",
        model="DSP-1760 (single axis)",
        technology="FOG",
        grade="tactical",
        source=(
            "KVH/EMCORE DSP-1760 data sheet (EMCORE DS_DSP1760, 2024; revision not shown in the quotes), figures "
            "as quoted in github.com/tim-balloon/TIMflight/issues/77 (ARW <= 0.012 deg/sqrt(h), i.e. <= 0.7 "
            "deg/h/sqrt(Hz)) and in the NCLT dataset sensor notes (bias instability 0.05 deg/h typical, "
            "+-490 deg/s). KVH's own technical manuals exist in public mirrors (DSP-1760 Multi-axis Gyroscope "
            "Technical Manual, KVH part 54-0924 Rev. A, 2013; Unhoused DSP-1760 Technical Manual, 54-1210 Rev. A, "
            "2016), but only their covers and contents pages could be read, not the specification tables: no "
            "figure is taken from them"
        ),
        range_dps=490.0,
        bias_instability_dph=0.05,
        arw=0.012,
        notes=(
            "ARW 0.012 deg/sqrt(h) is the sheet's maximum, bias instability 0.05 deg/h its typical value; "
            "KVH states both from the Allan variance (ADEV minimum); scale factor, temperature and "
            "g-sensitivity figures were not in the quoting sources: left unset"
        ),
    ),
    Datasheet(
        name="astrix-120",
        source_kind="primary",
        manufacturer="Airbus Defence and Space",
        model="Astrix 120 (FOG 120 channel)",
        technology="FOG",
        grade="navigation",
        source=(
            "Airbus Defence and Space product page 'Astrix 120 fiber optic gyro' "
            "(space-airbusds.com, equipements/astrix-120-fiber-optic-gyro; no document revision)"
        ),
        bias_instability_dph=0.01,
        arw=0.002,
        scale_factor_repeatability=100.0,
        notes=(
            "bias stability 0.01 deg/h read as the ADEV minimum; scale factor 100 ppm taken as the 1 sigma "
            "scale-factor error; range, temperature coefficients and resolution not given: left unset"
        ),
    ),
    Datasheet(
        name="astrix-200",
        source_kind="primary",
        manufacturer="Airbus Defence and Space",
        model="Astrix 200 (FOG 200 channel)",
        technology="FOG",
        grade="navigation",
        source=(
            "Airbus Defence and Space product page 'Astrix 200 fiber optic gyro' "
            "(space-airbusds.com, equipements/astrix-200-fiber-optic-gyro-1j8; no document revision)"
        ),
        bias_instability_dph=0.002,
        arw=0.0002,
        scale_factor_repeatability=20.0,
        notes=(
            "bias stability 0.002 deg/h read as the ADEV minimum; the page's ARW unit lost its root sign in the "
            "copy read ('0,0002 deg/'): read as deg/sqrt(h), the unit the same vendor's Astrix 120 page prints "
            "for the same line; scale factor 20 ppm taken as the 1 sigma scale-factor error; a satellite IMU "
            "beyond navigation grade (the closest grade here)"
        ),
    ),
    Datasheet(
        name="lsm6dsv",
        source_kind="secondary",
        manufacturer="STMicroelectronics",
        model="LSM6DSV (+-4000 deg/s full-scale option)",
        technology="MEMS",
        grade="consumer",
        source=(
            "ST LSM6DSV data sheet (st.com/resource/en/datasheet/lsm6dsv.pdf; revision not seen), figures as "
            "quoted from it in the Luxonis LSM6DSV sensor page (docs.luxonis.com/hardware/platform/sensors/imu/"
            "lsm6dsv), 'Native silicon characteristics': gyroscope full scale up to +-4000 dps, 140 mdps/LSB "
            "at +-4000 dps, rate noise density 2.8 mdps/sqrt(Hz) typical"
        ),
        range_dps=4000.0,
        noise_density=0.0028,
        noise_density_sided="two",
        resolution=0.140,
        accel_range_g=16.0,
        accel_noise_density_ug=60.0,
        accel_resolution_mg=0.488,
        notes=(
            "the high-range part: its +-4000 deg/s option (the paper-001 class is +-3600); the quoted sheet "
            "figures print no bias instability, so none is drawn (no 1/f term) and the fit-back checks the "
            "ARW only; the noise density's PSD convention is not stated: taken two-sided (ARW = 60 x density, "
            "0.168 deg/sqrt(h)); resolution: 140 mdps/LSB at +-4000 dps, so below an output rate of about "
            "(q/N)^2 = 2500 Hz the LSB exceeds the per-sample noise and the output is not dithered; output "
            "rate up to 7680 Hz (the maximum, no default stated: left unset); ST's own datasheet text was not "
            "read first-hand; accelerometers from the same table: the +-16 g option (the high-range one), "
            "0.488 mg/LSB at +-16 g, noise density 60 ug/sqrt(Hz) typical in high-performance mode (two-sided, as "
            "the gyro's); no accelerometer bias instability quoted (no 1/f term); the page's own 'characterized "
            "noise parameters' are Luxonis measurements without units, not the sheet's: not used"
        ),
    ),
    Datasheet(
        name="bmi088",
        source_kind="primary",
        manufacturer="Bosch Sensortec",
        model="BMI088 (gyroscope at +-2000 deg/s, ODR 400 Hz, filter bandwidth 47 Hz)",
        technology="MEMS",
        grade="consumer",
        source=(
            "Bosch Sensortec BMI088 Data Sheet, document BST-BMI088-DS000-19, revision 1.9 (January 2024): "
            "Table 5 'Gyroscope specifications' (section 1.3, p. 10) and Table 4 'Accelerometer specifications' "
            "(section 1.2, p. 9); the range and resolution also in section 5.5.5 GYRO_RANGE (p. 39); read from a "
            "public text conversion of the PDF"
        ),
        range_dps=2000.0,
        noise_density=0.014,
        noise_density_sided="one",
        rms_noise=0.1,
        bandwidth=47.0,
        output_rate=400.0,
        resolution=1.0 / 16.384,
        bias_repeatability=1.0 * 3600.0,
        bias_tempco=0.015 * 3600.0,
        scale_factor_repeatability=0.01 * 1e6,
        scale_factor_tempco=0.03 * 1e4,
        g_sensitivity=0.1 * 3600.0,
        accel_range_g=3.0,
        accel_noise_density_ug=160.0,
        accel_bias_repeatability_mg=20.0,
        accel_bias_tempco_mg_per_k=0.2,
        accel_scale_factor_tempco_ppm_per_k=0.002 * 1e4,
        accel_resolution_mg=1000.0 / 10920.0,
        notes=(
            "Table 5: range +-125..+-2000 deg/s (2000 taken), sensitivity 16.384 LSB/(deg/s) at +-2000 (resolution "
            "61.0 mdeg/s), sensitivity tolerance +-1 % and zero-rate offset +-1 deg/s (typical values, taken as the "
            "1 sigma of the unit-to-unit spread: the sheet's min/max are +-3 sigma, its typical values are not "
            "defined further), sensitivity change over temperature +-0.03 %/K (300 ppm/K), zero-rate offset change "
            "over temperature +-0.015 deg/s per K (54 deg/h/K), g-sensitivity 0.1 deg/s/g (a maximum), output "
            "noise 0.1 deg/s rms at BW = 47 Hz '(@ 0.014 deg/s/sqrt(Hz))': 0.014 x sqrt(47) = 0.096, so the density "
            "is ONE-sided; the 47 Hz bandwidth is the one the sheet pairs with ODR 400 Hz (GYRO_BANDWIDTH 0x03, the "
            "register table is a figure in the copy read, the pairing from Bosch's register map); the signs of the "
            "coefficients are not printed (taken positive); no bias instability printed (no 1/f term); "
            "accelerometers from Table 4: range +-3 g (the option the noise density is given for), output noise "
            "density 160 ug/sqrt(Hz) on x and y (190 on z; one-sided, as the gyro's), sensitivity 10920 LSB/g at 3 g, "
            "zero-g offset 20 mg typical (taken as 1 sigma), offset drift < 0.2 mg/K (the bound taken), sensitivity "
            "drift 0.002 %/K; bandwidth depends on ODR and OSR (5..280 Hz): unset"
        ),
    ),
    Datasheet(
        name="icm-42688-p",
        source_kind="primary",
        manufacturer="TDK InvenSense",
        model="ICM-42688-P (gyroscope at +-2000 deg/s, ODR 1 kHz, UI filter 100 Hz)",
        technology="MEMS",
        grade="consumer",
        source=(
            "TDK InvenSense ICM-42688-P Datasheet, Document Number DS-000347, Revision 1.8 (07/27/2023): Table 1 "
            "'Gyroscope Specifications' (section 3.1, p. 11) and Table 2 'Accelerometer Specifications' (section 3.2, "
            "p. 12); read from a public text conversion of the PDF"
        ),
        range_dps=2000.0,
        noise_density=0.0028,
        noise_density_sided="one",
        rms_noise=0.028,
        bandwidth=100.0,
        output_rate=1000.0,
        resolution=1.0 / 16.4,
        bias_repeatability=0.5 * 3600.0,
        bias_tempco=0.005 * 3600.0,
        scale_factor_repeatability=0.005 * 1e6,
        scale_factor_tempco=0.005 * 1e4,
        accel_range_g=16.0,
        accel_noise_density_ug=65.0,
        accel_bias_repeatability_mg=20.0,
        accel_bias_tempco_mg_per_k=0.15,
        accel_scale_factor_repeatability_ppm=0.005 * 1e6,
        accel_scale_factor_tempco_ppm_per_k=0.005 * 1e4,
        accel_resolution_mg=1000.0 / 2048.0,
        notes=(
            "Table 1: full scale +-2000 deg/s (GYRO_FS_SEL = 0), 16.4 LSB/(deg/s), sensitivity scale factor initial "
            "tolerance +-0.5 %, its variation over temperature +-0.005 %/degC (0..70 degC; 50 ppm/K), initial ZRO "
            "tolerance +-0.5 deg/s and ZRO variation +-0.005 deg/s/degC (18 deg/h/K), all typical values taken as "
            "1 sigma and positive (signs not printed); rate noise spectral density 0.0028 deg/s/sqrt(Hz) at 10 Hz "
            "and total RMS noise 0.028 deg/s at bandwidth 100 Hz, 'calculated from the rate noise spectral density' "
            "(note 4): 0.0028 x sqrt(100) = 0.028, so the density is ONE-sided; the 100 Hz bandwidth is the sheet's "
            "RMS condition, ODR 1 kHz the output rate chosen with it (the sheet allows 12.5..32000 Hz; an "
            "assumption); no bias instability and no g-sensitivity printed; accelerometers from Table 2: +-16 g, "
            "2048 LSB/g, noise 65 ug/sqrt(Hz) on x and y (70 on z), initial tolerance +-0.5 %, sensitivity change "
            "+-0.005 %/degC, zero-g +-20 mg, zero-g change +-0.15 mg/degC (typical values as 1 sigma)"
        ),
    ),
    Datasheet(
        name="icm-42686-p",
        source_kind="primary",
        manufacturer="TDK InvenSense",
        model="ICM-42686-P (+-4000 deg/s)",
        technology="MEMS",
        grade="consumer",
        source=(
            "TDK InvenSense's sensor comparison table 'TDK-InvenSense sensors for smartphone, mobile & IoT "
            "applications' on p. 1 of the ICM-42688-P Datasheet DS-000347 Revision 1.8 (the ICM-42686-P column); "
            "the part's own sheet was not read"
        ),
        range_dps=4000.0,
        noise_density=0.0053,
        noise_density_sided="one",
        bias_tempco=0.010 * 3600.0,
        resolution=8000.0 / 65536.0,
        accel_range_g=32.0,
        accel_noise_density_ug=70.0,
        notes=(
            "the table's column: gyro noise 5.3 mdps/sqrt(Hz), gyro offset temperature stability +-10 mdps/degC "
            "(36 deg/h/K, taken positive), range +-4000 deg/s at 16 bits (resolution 8000/2^16 deg/s, the 16-bit "
            "word over the full scale: an assumption), accelerometer noise 70 ug/sqrt(Hz) and +-32 g; the density "
            "is taken ONE-sided, the convention the same vendor's ICM-42688-P sheet shows (its RMS noise is the "
            "density x sqrt(bandwidth)); no bandwidth, repeatability, scale-factor or bias-instability figures in "
            "the table: unset"
        ),
    ),
)