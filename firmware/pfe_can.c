/* pfe_can.c - J1939 identifiers (contract in pfe_can.h). */
#include "pfe_can.h"

#define J1939_PF_PDU2_MIN 240U     /* PF >= 240: PDU2, PS is a group extension */
#define J1939_PGN_MASK 0x3FFFFUL   /* EDP, DP, PF, PS */

static uint32_t pdu_format(uint32_t id)
{
    return (id >> 16) & 0xFFU;
}

uint32_t pfe_j1939_pgn(uint32_t id)
{
    uint32_t pgn = (id >> 8) & J1939_PGN_MASK;
    if (pdu_format(id) < J1939_PF_PDU2_MIN) {
        pgn &= ~(uint32_t)0xFFU; /* PDU1: PS is the destination, not part of the PGN */
    }
    return pgn;
}

uint8_t pfe_j1939_source(uint32_t id)
{
    return (uint8_t)(id & 0xFFU);
}

uint8_t pfe_j1939_destination(uint32_t id)
{
    if (pdu_format(id) < J1939_PF_PDU2_MIN) {
        return (uint8_t)((id >> 8) & 0xFFU);
    }
    return PFE_J1939_ADDR_GLOBAL;
}

uint32_t pfe_j1939_id(uint8_t priority, uint32_t pgn, uint8_t destination, uint8_t source)
{
    uint32_t pdu = pgn & J1939_PGN_MASK;
    if (((pdu >> 8) & 0xFFU) < J1939_PF_PDU2_MIN) {
        pdu = (pdu & ~(uint32_t)0xFFU) | (uint32_t)destination;
    }
    return PFE_CAN_EFF_FLAG | (((uint32_t)priority & 7U) << 26) | (pdu << 8) | (uint32_t)source;
}
