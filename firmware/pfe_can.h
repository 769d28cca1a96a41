/*
 * pfe_can.h - a CAN frame as the module sees it, and J1939 identifiers.
 *
 * The firmware never talks to a CAN controller: a HAL backend (hal/) moves
 * these frames between the bus and the ECU loop. Classic CAN only (J1939
 * uses 29-bit identifiers and at most 8 data bytes).
 *
 * A J1939 identifier (SAE J1939-21): priority (3 bits) | EDP, DP, PF, PS
 * (18 bits, the PGN when PF >= 240; when PF < 240 PS is the destination
 * address and the PGN carries PS = 0) | source address (8 bits).
 */
#ifndef PFE_CAN_H
#define PFE_CAN_H

#include <stdbool.h>
#include <stdint.h>

#define PFE_CAN_MAX_DLC 8U
#define PFE_CAN_EFF_FLAG 0x80000000UL /* id is a 29-bit identifier */
#define PFE_CAN_ID_MASK 0x1FFFFFFFUL

typedef struct {
    uint32_t id;                 /* 29-bit id | PFE_CAN_EFF_FLAG, or an 11-bit id */
    uint8_t dlc;                 /* 0 .. 8 */
    uint8_t data[PFE_CAN_MAX_DLC];
} pfe_can_frame_t;

#define PFE_J1939_ADDR_NULL 0xFEU    /* "cannot claim" source address */
#define PFE_J1939_ADDR_GLOBAL 0xFFU  /* destination: everyone */

/* PGN of a 29-bit identifier, destination address masked out for PDU1. */
uint32_t pfe_j1939_pgn(uint32_t id);
uint8_t pfe_j1939_source(uint32_t id);
/* Destination of a PDU1 identifier (PF < 240); PFE_J1939_ADDR_GLOBAL for PDU2. */
uint8_t pfe_j1939_destination(uint32_t id);
/* Identifier (with PFE_CAN_EFF_FLAG) from priority 0..7, PGN, destination
 * (used for PDU1 PGNs only) and source address. */
uint32_t pfe_j1939_id(uint8_t priority, uint32_t pgn, uint8_t destination, uint8_t source);

#endif /* PFE_CAN_H */
