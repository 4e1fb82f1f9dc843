"""Physical constants, SI units, each with its source.

Examples
--------
>>> from xnavlab.core import constants
>>> round(constants.AU / constants.C, 3)   # light time over 1 au, s
499.005
"""

__all__ = [
    "C",
    "AU",
    "DAY",
    "J2000_JD",
    "KPC",
    "GM_SUN",
    "GM_EARTH",
    "GM_MARS",
    "GM_JUPITER",
    "R_MARS",
    "J2_MARS",
    "J2_MARS_RADIUS",
    "R_EARTH",
    "J2_EARTH",
    "J2_EARTH_RADIUS",
    "SOURCES",
]

#: Speed of light in vacuum, m/s (exact by the SI definition of the metre).
C = 299_792_458.0
#: Astronomical unit, m (exact, IAU 2012 Resolution B2).
AU = 149_597_870_700.0
#: Seconds in a day.
DAY = 86_400.0
#: Julian date of the J2000 epoch, TDB (2000-01-01 12:00 TDB).
J2000_JD = 2_451_545.0
#: Kiloparsec, m (IAU 2015 Resolution B2: 1 pc = 648000/pi au).
KPC = 1.0e3 * 648_000.0 / 3.141592653589793 * AU
#: Sun's GM, m^3/s^2 (IAU 2009 system of astronomical constants, TDB-compatible).
GM_SUN = 1.327_124_400_41e20
#: Earth's GM, m^3/s^2, TDB-compatible (IERS Conventions 2010; TCG value 3.986004418e14).
GM_EARTH = 3.986_004_356e14
#: Mars's GM, m^3/s^2 (JPL MRO120D gravity field, Konopliv et al. 2016).
GM_MARS = 4.282_837_58e13
#: Jupiter system GM, m^3/s^2 (JPL DE421 header, GM5 = 2.825345909524226e-7 au^3/day^2).
GM_JUPITER = 1.267_127_648e17
#: Mars equatorial radius, m (IAU WGCCRE 2015, Archinal et al. 2018).
R_MARS = 3_396_190.0
#: Mars J2, unnormalised (Konopliv et al. 2006, MGS95J); use with :data:`J2_MARS_RADIUS`.
J2_MARS = 1.955_45e-3
#: Reference radius of the MGS95J field, m: a zonal coefficient is defined with its own
#: radius (``J2 mu R^2`` is what the field fixes), not with the IAU :data:`R_MARS`.
J2_MARS_RADIUS = 3_396_000.0
#: Earth equatorial radius, m (WGS-84).
R_EARTH = 6_378_137.0
#: Earth J2, unnormalised (EGM2008, sqrt(5) x 0.484165143790815e-3); use with
#: :data:`J2_EARTH_RADIUS`.
J2_EARTH = 1.082_626_68e-3
#: Reference radius of EGM2008, m (not the WGS-84 :data:`R_EARTH`; they differ by 0.7 m).
J2_EARTH_RADIUS = 6_378_136.3

#: Where each value comes from, for the notation page and the chapters.
SOURCES = {
    "C": "SI definition of the metre (exact)",
    "AU": "IAU 2012 Resolution B2 (exact)",
    "KPC": "IAU 2015 Resolution B2 (1 pc = 648000/pi au)",
    "GM_SUN": "IAU 2009 system of astronomical constants (TDB)",
    "GM_EARTH": "IERS Conventions 2010, TDB-compatible value",
    "GM_MARS": "JPL MRO120D gravity field (Konopliv et al. 2016)",
    "GM_JUPITER": "JPL DE421 header constant GM5 (Jupiter system)",
    "R_MARS": "IAU WGCCRE 2015 (Archinal et al. 2018)",
    "J2_MARS": "Konopliv et al. 2006, MGS95J",
    "J2_MARS_RADIUS": "Konopliv et al. 2006, MGS95J reference radius",
    "R_EARTH": "WGS-84",
    "J2_EARTH": "EGM2008 (Pavlis et al. 2012)",
    "J2_EARTH_RADIUS": "EGM2008 reference radius (Pavlis et al. 2012)",
}
