#!/usr/bin/env python3
"""Writes the UBX fuzz seed corpus (test/fuzz/corpus/ubx): small generated
recordings, no bytes of any real recording. Field layouts: u-blox F9 interface
description (UBX-RXM-RAWX, UBX-RXM-SFRBX), IS-GPS-200 20.3.3 (LNAV subframes
1-3), Galileo OS SIS ICD 4.3 (I/NAV pages, word types 1-5).

Known values used by test_ubx_decoder (GeneratedSeeds): the LNAV frame is G07 with
IODC 0x14D / IODE 0x4D, sqrt(A) 5153.5 m^0.5, toe 410400 s, week 2381; the I/NAV
words are E11 with IODnav 77, sqrt(A) 5440.5 m^0.5, toe 410400 s, GST week 1357.
"""
import os, struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'corpus', 'ubx')


def frame(cls, mid, payload):
    body = bytes([cls, mid]) + struct.pack('<H', len(payload)) + payload
    a = b = 0
    for x in body:
        a = (a + x) & 0xFF
        b = (b + a) & 0xFF
    return b'\xb5\x62' + body + bytes([a, b])


def rawx(tow, week, meas):
    p = struct.pack('<dHbBBB2x', tow, week, 18, len(meas), 1, 1)
    for (pr, cp, do, gnss, sv, sig, lock, cn0, cpstd, trk) in meas:
        p += struct.pack('<ddfBBBBHBBBBBx', pr, cp, do, gnss, sv, sig, 7, lock, cn0, 3, cpstd, 2, trk)
    return frame(0x02, 0x15, p)


class Bits:
    def __init__(self, n):
        self.v = [0] * n

    def put(self, start, length, value):  # start 0-based, MSB first; two's complement
        value &= (1 << length) - 1
        for i in range(length):
            self.v[start + i] = (value >> (length - 1 - i)) & 1

    def get(self, start, length):
        x = 0
        for i in range(length):
            x = (x << 1) | self.v[start + i]
        return x


def sfrbx(gnss, sv, sig, words):
    p = struct.pack('<BBBBBBBB', gnss, sv, sig, 0, len(words), 0, 2, 0)
    for w in words:
        p += struct.pack('<I', w)
    return frame(0x02, 0x13, p)


def lnav_subframe(sfid, tow_count, fields):
    b = Bits(300)
    b.put(0, 8, 0x8B)                 # preamble
    b.put(30, 17, tow_count)          # HOW TOW count
    b.put(49, 3, sfid)                # subframe id (bits 50-52)
    for (n, length, value) in fields:  # ICD bit numbers (1-based)
        b.put(n - 1, length, value)
    return [b.get(30 * w, 30) for w in range(10)]  # parity bits left zero


def split32(n1, n2, value):
    value &= 0xFFFFFFFF
    return [(n1, 8, value >> 24), (n2, 24, value & 0xFFFFFF)]


def lnav_frame(sv=7, tow_count=68100):
    iodc, iode = 0x14D, 0x4D
    sf1 = [(61, 10, 2381 % 1024), (73, 4, 0), (77, 6, 0), (83, 2, iodc >> 8), (197, 8, -4),
           (211, 8, iodc & 0xFF), (219, 16, 410400 // 16), (241, 8, 0), (249, 16, -50), (271, 22, 123456)]
    sf2 = [(61, 8, iode), (69, 16, 1000), (91, 16, 12000)] + split32(107, 121, 1234567890) + \
          [(151, 16, -800)] + split32(167, 181, int(0.01 * 2**33)) + [(211, 16, 900)] + \
          split32(227, 241, int(5153.5 * 2**19)) + [(271, 16, 410400 // 16), (287, 1, 0)]
    sf3 = [(61, 16, 20)] + split32(77, 91, -987654321) + [(121, 16, -30)] + split32(137, 151, 660000000) + \
          [(181, 16, 7000)] + split32(197, 211, 400000000) + [(241, 24, -20000), (271, 8, iode), (279, 14, -100)]
    return b''.join(sfrbx(0, sv, 0, lnav_subframe(i + 1, tow_count + i, f)) for i, f in enumerate([sf1, sf2, sf3]))


def crc24q(data):
    crc = 0
    for byte in data:
        crc ^= byte << 16
        for _ in range(8):
            crc <<= 1
            if crc & 0x1000000:
                crc ^= 0x1864CFB
    return crc & 0xFFFFFF


def inav_page(word_bits):
    even, odd = Bits(128), Bits(128)
    even.put(0, 1, 0); even.put(1, 1, 0)
    for i in range(112):
        even.v[2 + i] = word_bits.v[i]
    odd.put(0, 1, 1); odd.put(1, 1, 0)
    for i in range(16):
        odd.v[2 + i] = word_bits.v[112 + i]
    crc_in = Bits(200)
    for i in range(114):
        crc_in.v[4 + i] = even.v[i]
    for i in range(82):
        crc_in.v[118 + i] = odd.v[i]
    data = bytes(crc_in.get(8 * k, 8) for k in range(25))
    odd.put(82, 24, crc24q(data))
    words = [even.get(32 * k, 32) for k in range(4)] + [odd.get(32 * k, 32) for k in range(4)]
    return words


def inav_words(sv=11, iod=77):
    def word(fields):
        b = Bits(128)
        at = 0
        for (length, value) in fields:
            b.put(at, length, value)
            at += length
        return b
    w1 = word([(6, 1), (10, iod), (14, 410400 // 60), (32, 1111111111), (32, int(0.0002 * 2**33)),
               (32, int(5440.5 * 2**19))])
    w2 = word([(6, 2), (10, iod), (32, -555555555), (32, 650000000), (32, 222222222), (14, 50)])
    w3 = word([(6, 3), (10, iod), (24, -15000), (16, 9000), (16, -600), (16, 700), (16, 5000), (16, -300),
               (8, 107)])
    w4 = word([(6, 4), (10, iod), (6, sv), (16, 15), (16, -25), (14, 410400 // 60), (31, -2000000),
               (21, -300), (6, 0)])
    w5 = word([(6, 5), (11, 40), (11, 10), (14, 0), (5, 0), (10, 7), (10, 8), (2, 0), (2, 0), (1, 0), (1, 0),
               (12, 1357), (20, 410430)])
    return b''.join(sfrbx(2, sv, 1, inav_page(w)) for w in [w1, w2, w3, w4, w5])


def main():
    os.makedirs(OUT, exist_ok=True)
    meas = [(2.1e7, 1.1e8, -500.0, 0, 7, 0, 5000, 44, 2, 7), (2.1e7 + 3, 8.6e7, -390.0, 0, 7, 3, 5000, 40, 3, 15),
            (2.4e7, 1.26e8, 800.0, 2, 11, 0, 2000, 41, 2, 7), (2.4e7 + 2, 9.4e7, 600.0, 2, 11, 4, 0, 38, 15, 1),
            (3.8e7, 2.0e8, 300.0, 1, 133, 0, 9000, 39, 2, 7), (2.2e7, 1.15e8, 100.0, 6, 5, 0, 100, 35, 4, 7)]
    epochs = b''.join(rawx(408600.0 + 0.25 * k, 2381, meas) for k in range(4))
    seeds = {
        'rawx_epochs.ubx': epochs,
        'lnav_frame.ubx': rawx(408600.0, 2381, meas[:1]) + lnav_frame(),
        'inav_words.ubx': rawx(408600.0, 2381, meas[2:3]) + inav_words(),
        'mixed_with_nmea.ubx': b'$GNGGA,,,,,,0,00,99.99,,,,,,*56\r\n' + epochs[:200] + frame(0x01, 0x07, bytes(92)) +
                               b'\xb5\x62\x02\x15\xff\xff' + frame(0x7F, 0x01, b'abc') + epochs[200:],
        'bad_checksum_truncated.ubx': epochs[:-1] + b'\x00' + lnav_frame()[:-30],
    }
    for name, data in seeds.items():
        with open(os.path.join(OUT, name), 'wb') as f:
            f.write(data)
        print(name, len(data))


if __name__ == '__main__':
    main()
